// What Minstrel (minstrel.h) and Minstrel-HT (minstrel_ht.h) share as a
// station's RateManager: per-destination state made at first use (by Choose,
// or by a report that comes first: an internal collision of a frame not yet
// sent, as ns-3 makes its station), and every report forwarded to the
// algorithm under ns-3's name. A manager adds Choose: how its rate indices map
// to the medium's rate table.
#ifndef SITLNET_MAC_PHY_SIM_MINSTREL_FAMILY_RATE_MANAGER_H_
#define SITLNET_MAC_PHY_SIM_MINSTREL_FAMILY_RATE_MANAGER_H_

#include <utility>

#include "mac_phy_sim/per_destination.h"
#include "mac_phy_sim/rate_manager.h"

namespace sitlnet::mac {

template <typename Algorithm, typename RemoteState>
class MinstrelFamilyRateManager : public RateManager {
 public:
  explicit MinstrelFamilyRateManager(Algorithm algorithm) : minstrel_(std::move(algorithm)) {}

  void ReportRtsFailed(const MacAddress& destination, TimeNs now_ns) override {
    minstrel_.ReportRtsFailed(Remote(destination, now_ns));
  }
  void ReportFinalRtsFailed(const MacAddress& destination, TimeNs now_ns) override {
    minstrel_.ReportFinalRtsFailed(Remote(destination, now_ns));
  }
  void ReportDataOk(const MacAddress& destination, double /*data_snr*/, TimeNs now_ns) override {
    minstrel_.ReportDataOk(Remote(destination, now_ns), now_ns);
  }
  void ReportDataFailed(const MacAddress& destination, TimeNs now_ns) override {
    minstrel_.ReportDataFailed(Remote(destination, now_ns));
  }
  void ReportFinalDataFailed(const MacAddress& destination, TimeNs now_ns) override {
    minstrel_.ReportFinalDataFailed(Remote(destination, now_ns), now_ns);
  }
  bool NeedRetransmission(const MacAddress& destination, bool /*normally*/,
                          TimeNs now_ns) override {
    return minstrel_.NeedRetransmission(Remote(destination, now_ns));
  }
  void ReportAmpduTxStatus(const MacAddress& destination, int mpdus_ok, int mpdus_failed,
                           double /*rx_snr*/, double /*data_snr*/, TimeNs now_ns) override {
    minstrel_.ReportAmpduTxStatus(Remote(destination, now_ns), mpdus_ok, mpdus_failed, now_ns);
  }

 protected:
  RemoteState& Remote(const MacAddress& destination, TimeNs now_ns) {
    return remotes_.Get(destination, [&] { return minstrel_.NewRemote(now_ns); });
  }

 private:
  Algorithm minstrel_;
  PerDestination<RemoteState> remotes_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MINSTREL_FAMILY_RATE_MANAGER_H_

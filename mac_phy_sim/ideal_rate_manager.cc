// ns-3 3.37's IdealWifiManager: per destination, the highest rate whose SNR
// threshold for ideal_ber (RateEntry::ideal_snr_threshold) is below the SNR
// the destination last measured on an acknowledged frame of ours; RTS at the
// highest basic rate whose threshold is below it.
#include <utility>
#include <vector>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

class IdealRateManager final : public RateManager {
 public:
  explicit IdealRateManager(const std::vector<RateEntry>& rates) : rates_(rates) {}

  TxRates Choose(const MacAddress& destination, TimeNs /*now_ns*/) override {
    const double snr = LastSnr(destination);
    TxRates out;
    out.data = &rates_.front();
    for (const RateEntry& entry : rates_) {
      if (entry.ideal_snr_threshold < snr &&
          entry.data.mode.rate_mbps > out.data->data.mode.rate_mbps) {
        out.data = &entry;
      }
      if (entry.basic && entry.ideal_snr_threshold < snr &&
          (out.rts == nullptr || entry.ideal_snr_threshold > out.rts->ideal_snr_threshold)) {
        out.rts = &entry;
      }
    }
    if (out.rts == nullptr) out.rts = &rates_.front();  // ns-3: the default mode.
    out.rts_mode = &out.rts->data;
    return out;
  }
  void ReportRtsOk(const MacAddress& destination, double rts_snr) override {
    Remember(destination, rts_snr);
  }
  void ReportDataOk(const MacAddress& destination, double data_snr, TimeNs /*now_ns*/) override {
    Remember(destination, data_snr);
  }
  void ReportAmpduTxStatus(const MacAddress& destination, int /*mpdus_ok*/, int /*mpdus_failed*/,
                           double /*rx_snr*/, double data_snr, TimeNs /*now_ns*/) override {
    if (data_snr == 0) return;  // ns-3: a zero report is not saved.
    Remember(destination, data_snr);
  }

 private:
  double LastSnr(const MacAddress& destination) const {
    for (const auto& [mac, snr] : last_snr_) {
      if (mac == destination) return snr;
    }
    return 0;  // ns-3: m_lastSnrObserved starts at 0, so the lowest rate.
  }
  void Remember(const MacAddress& destination, double snr) {
    for (auto& [mac, last] : last_snr_) {
      if (mac == destination) {
        last = snr;
        return;
      }
    }
    last_snr_.emplace_back(destination, snr);
  }

  const std::vector<RateEntry>& rates_;  // State::rates: never resized.
  std::vector<std::pair<MacAddress, double>> last_snr_;  // Linear, per destination.
};

}  // namespace

std::unique_ptr<RateManager> MakeIdealRateManager(const State& s) {
  return std::make_unique<IdealRateManager>(s.rates);
}

}  // namespace sitlnet::mac

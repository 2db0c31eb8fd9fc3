// Rate control behind one interface (ns-3's WifiRemoteStationManager split):
// one RateManager per transmitting station, keeping per-destination state as
// ns-3 keeps per-remote-station state. The frame exchange asks it for the
// rates of each attempt and reports every outcome, named as ns-3's Report*
// calls; a manager ignores what it does not use. Implementations:
//   rate_control.cc          the constant rate (ConstantRateWifiManager)
//   ideal_rate_manager.cc    ns-3 3.37's IdealWifiManager
//   minstrel_rate_manager.cc ns-3 3.37's MinstrelWifiManager (minstrel.h)
//   minstrel_ht_rate_manager.cc ns-3 3.37's MinstrelHtWifiManager (minstrel_ht.h), n/ac
#ifndef SITLNET_MAC_PHY_SIM_RATE_MANAGER_H_
#define SITLNET_MAC_PHY_SIM_RATE_MANAGER_H_

#include <cstdint>
#include <memory>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

struct ModeEntry;
struct RateEntry;

// The rates of one attempt of a unicast frame.
struct TxRates {
  const RateEntry* data = nullptr;     // DATA rate; its control entry times the ACK.
  const RateEntry* rts = nullptr;      // Rate whose cts_ns times the CTS answering the RTS.
  const ModeEntry* rts_mode = nullptr;  // The RTS's own mode.
};

class RateManager {
 public:
  virtual ~RateManager() = default;

  // ns-3's GetDataTxVector / GetRtsTxVector for the next attempt to `destination`.
  virtual TxRates Choose(const MacAddress& destination, TimeNs now_ns) = 0;

  // Outcomes, in the order ns-3 3.37's FrameExchangeManager reports them, at `now_ns` (a
  // report may come before any Choose: an internal collision). SNRs are linear:
  // what the destination measured on our RTS or DATA (ns-3's SnrTag in the CTS/ACK).
  virtual void ReportRtsOk(const MacAddress& /*destination*/, double /*rts_snr*/) {}
  virtual void ReportRtsFailed(const MacAddress& /*destination*/, TimeNs /*now_ns*/) {}
  virtual void ReportFinalRtsFailed(const MacAddress& /*destination*/, TimeNs /*now_ns*/) {}
  virtual void ReportDataOk(const MacAddress& /*destination*/, double /*data_snr*/,
                            TimeNs /*now_ns*/) {}
  virtual void ReportDataFailed(const MacAddress& /*destination*/, TimeNs /*now_ns*/) {}
  virtual void ReportFinalDataFailed(const MacAddress& /*destination*/, TimeNs /*now_ns*/) {}
  // Whether a failed frame is tried again; `normally` is the retry-limit answer (ns-3's
  // DoNeedRetransmission: Minstrel replaces it by its retry chain's length).
  virtual bool NeedRetransmission(const MacAddress& /*destination*/, bool normally,
                                  TimeNs /*now_ns*/) {
    return normally;
  }
  // The outcome of one A-MPDU at one rate: MPDUs acknowledged and not, the SNR of the Block
  // Ack and what the destination measured on the A-MPDU (ns-3's DoReportAmpduTxStatus; a
  // manager without A-MPDU support ignores it, as ns-3's base class does). The entry point
  // for the A-MPDU code.
  virtual void ReportAmpduTxStatus(const MacAddress& /*destination*/, int /*mpdus_ok*/,
                                   int /*mpdus_failed*/, double /*rx_snr*/, double /*data_snr*/,
                                   TimeNs /*now_ns*/) {}
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_RATE_MANAGER_H_

// PHY constants per standard: rates, modulation, PPDU airtime, interframe
// spaces, contention windows, control-response rates. Numbers cite IEEE
// 802.11-2016 (clause 15 DSSS, 16 HR/DSSS, 17 OFDM, 18 ERP).
#ifndef SITLNET_MAC_PHY_SIM_PHY_MODE_H_
#define SITLNET_MAC_PHY_SIM_PHY_MODE_H_

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

enum class Modulation : uint8_t { kBpsk, kQpsk, kQam16, kQam64, kDbpsk, kDqpsk, kCck55, kCck11 };

// One transmission mode: what the error model and the airtime need.
struct PhyMode {
  double rate_mbps = 0;
  Modulation modulation = Modulation::kBpsk;
  int code_rate_b = 1;  // Convolutional code: 1 = 1/2, 2 = 2/3, 3 = 3/4 (0 for DSSS).
  bool ofdm = true;
};

// The mode of `rate_mbps` in `standard`; throws Error if the standard lacks it.
PhyMode ModeFor(Standard standard, double rate_mbps);

// Mode of the PHY header (SIGNAL field / PLCP header): 6 Mb/s BPSK 1/2 for
// OFDM, 1 Mb/s DBPSK for DSSS; and how many bits of it the error model sees.
PhyMode HeaderModeFor(Standard standard);
int HeaderBits(Standard standard);              // 24 (SIGNAL) or 48 (PLCP header).
TimeNs PreambleAndHeaderNs(Standard standard);  // 20 us (OFDM) or 192 us (long DSSS).
TimeNs SignalExtensionNs(Standard standard);    // 6 us for ERP-OFDM (18.3.2.4), else 0.

// Highest basic rate not above `rate_mbps` (10.6.6.5.2): control responses
// (ACK, CTS) and, here, RTS use it. Basic rates: 11a/g {6, 12, 24}, 11b {1, 2}.
double ControlRateFor(Standard standard, double rate_mbps);
// Lowest basic rate (used for EIFS).
double LowestBasicRate(Standard standard);

// Frame sizes on air (bytes, FCS included).
inline constexpr int kMacHeaderBytes = 24;
inline constexpr int kLlcSnapBytes = 8;
inline constexpr int kFcsBytes = 4;
inline constexpr int kAckBytes = 14;
inline constexpr int kCtsBytes = 14;
inline constexpr int kRtsBytes = 20;
inline constexpr int kEthernetHeaderBytes = 14;
inline constexpr int kMaxMsduBytes = 2304;  // 9.2.4.7.1
// An Ethernet II frame of E bytes becomes an MPDU of E + 22 bytes.
inline constexpr int MpduBytesForEthernet(int ethernet_bytes) {
  return ethernet_bytes - kEthernetHeaderBytes + kMacHeaderBytes + kLlcSnapBytes + kFcsBytes;
}

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_PHY_MODE_H_

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

// The PHY header of a PPDU: how long preamble + header last, the mode and
// bit count the error model applies to the header, and the ERP signal
// extension. OFDM: 16 us preamble + 4 us SIGNAL (24 bits, 6 Mb/s BPSK 1/2),
// 17.3.2. DSSS long PPDU: 144 us preamble + 48 us PLCP header at 1 Mb/s
// DBPSK (15.3.3); short PPDU: 72 us + 24 us with the 48-bit header at 2 Mb/s
// DQPSK (16.2.2.3). ns-3 3.37 (GetPreambleForTransmission) uses the short
// format only for the HR/DSSS rates 5.5 and 11 Mb/s, never at 1 or 2 Mb/s.
struct PhyHeader {
  TimeNs preamble_and_header_ns = 0;
  TimeNs signal_extension_ns = 0;  // 6 us for ERP-OFDM (18.3.2.4), else 0.
  PhyMode header_mode;
  int header_bits = 0;
};
PhyHeader HeaderFor(Standard standard, const PhyMode& mode, bool short_preamble);

// Exact PPDU duration of `psdu_bytes` in `mode` with `header`.
TimeNs PpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes);

// Control responses (ACK, CTS) and, here, RTS use the highest basic rate not
// above the rate of the frame they answer (10.6.6.5.2), of an allowed
// modulation class. The basic rate set is ns-3 3.37's for an ad hoc network:
// every mandatory rate of the PHY (AdhocWifiMac adds them all through
// WifiRemoteStationManager::AddAllSupportedModes): 11a {6, 12, 24}; 11b
// {1, 2, 5.5, 11} (all four DSSS/HR-DSSS rates are mandatory, 16.1.1), so an
// 11b ACK goes at the data rate; 11g {1, 2, 5.5, 11, 6, 12, 24}, and an ERP-OFDM
// frame is answered at 6, 12 or 24, a DSSS frame at its own rate.
double ControlRateFor(Standard standard, double rate_mbps);
// Lowest basic rate: group-addressed frames go at it by default (ns-3's
// GetNonUnicastMode: the first basic mode), and EIFS uses an ACK at it.
// 11a: 6 Mb/s; 11b and 11g: 1 Mb/s DSSS (ns-3's 11g PHY includes the DSSS
// rates, and its EIFS uses a 304 us ACK, WifiPhy::Configure80211g).
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

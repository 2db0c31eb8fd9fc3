// PHY constants per standard: rates, modulation, PPDU airtime, interframe
// spaces, contention windows, control-response rates. Numbers cite IEEE
// 802.11-2016 (clause 15 DSSS, 16 HR/DSSS, 17 OFDM, 18 ERP, 19 HT, 21 VHT);
// the HT/VHT numbers are ns-3 3.37's (HtPhy, VhtPhy) where it simplifies.
#ifndef SITLNET_MAC_PHY_SIM_PHY_MODE_H_
#define SITLNET_MAC_PHY_SIM_PHY_MODE_H_

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

enum class Modulation : uint8_t {
  kBpsk, kQpsk, kQam16, kQam64, kDbpsk, kDqpsk, kCck55, kCck11, kQam256
};

// Legacy: DSSS/HR-DSSS, OFDM, ERP-OFDM (one rate, 20 or 22 MHz); HT and VHT: an MCS.
enum class PhyFormat : uint8_t { kLegacy, kHt, kVht };

// One transmission mode: what the error model and the airtime need.
struct PhyMode {
  double rate_mbps = 0;  // Data rate, every spatial stream together.
  Modulation modulation = Modulation::kBpsk;
  // Convolutional code: 1 = 1/2, 2 = 2/3, 3 = 3/4, 5 = 5/6 (ns-3's "b value"); 0 for DSSS.
  int code_rate_b = 1;
  bool ofdm = true;  // OFDM symbols: OFDM, ERP-OFDM, HT, VHT.
  PhyFormat format = PhyFormat::kLegacy;
  int mcs = -1;  // HT: 0-15 (ns-3's HtMcs index); VHT: 0-9; legacy: -1.
  int spatial_streams = 1;
  int channel_width_mhz = 20;  // HT/VHT; legacy modes are 20 MHz (OFDM) or 22 MHz (DSSS).
  bool short_guard_interval = false;
};

// The mode of `rate_mbps` in `standard`; throws Error if the standard lacks it. For n/ac these are
// the legacy rates of the PHY underneath (11g at 2.4 GHz, 11a at 5 GHz): control and group frames.
PhyMode ModeFor(Standard standard, double rate_mbps);

// The HT (802.11n) or VHT (802.11ac) mode of `mcs` with `spatial_streams` (HT: must be mcs / 8 + 1),
// `channel_width_mhz` and the guard interval. Throws Error naming the rule for a combination the
// standard (or ns-3 3.37) does not allow. Rate: N_SD x N_BPSCS x R x N_SS bits per 4 us (3.6 us
// with the short GI) symbol, N_SD = 52, 108, 234 data subcarriers at 20, 40, 80 MHz (19.5, 21.5).
PhyMode McsModeFor(Standard standard, int mcs, int spatial_streams, int channel_width_mhz,
                   bool short_guard_interval);

// The data mode of a config (a/b/g: rate_mbps; n/ac: mcs, streams, width, GI), with a station's
// override of the rate or MCS. Throws Error naming the field.
PhyMode DataModeFor(const MediumConfig& config, const StationRadio& radio);

// Channel width (MHz) over which a receiver measures noise for a PPDU in `mode` (ns-3's
// GetMeasurementChannelWidth: the PPDU's width; 22 MHz for DSSS).
int MeasurementWidthMhz(const PhyMode& mode);

// Thermal noise kTB at 290 K (k = 1.3803e-23 J/K, as ns-3) over `bandwidth_hz`, plus the noise
// figure, in dBm: -101 dBm + NF at 20 MHz, 3 dB more per doubling.
double NoiseFloorDbm(double bandwidth_hz, double noise_figure_db);

// The PHY header of a PPDU: how long preamble + header last, the mode and
// bit count the error model applies to the header, and the ERP signal
// extension. OFDM: 16 us preamble + 4 us SIGNAL (24 bits, 6 Mb/s BPSK 1/2),
// 17.3.2. DSSS long PPDU: 144 us preamble + 48 us PLCP header at 1 Mb/s
// DBPSK (15.3.3); short PPDU: 72 us + 24 us with the 48-bit header at 2 Mb/s
// DQPSK (16.2.2.3). ns-3 3.37 (GetPreambleForTransmission) uses the short
// format only for the HR/DSSS rates 5.5 and 11 Mb/s, never at 1 or 2 Mb/s.
// HT-mixed (19.3.2) and VHT SU (21.3.2) PPDUs, as ns-3 3.37 times them: L-STF + L-LTF 16 us,
// L-SIG 4 us, HT-SIG or VHT-SIG-A 8 us, HT-STF or VHT-STF 4 us, one 4 us LTF per stream (1-2
// streams); ns-3 sends VHT-SIG-B only in MU PPDUs (VhtPhy::GetSigBDuration), so not here. The
// error model reads L-SIG (24 bits) and HT-SIG/VHT-SIG-A (48 bits) at 6 Mb/s BPSK 1/2.
struct PhyHeader {
  TimeNs preamble_and_header_ns = 0;
  // 6 us for OFDM-based PPDUs at 2.4 GHz: ERP-OFDM (18.3.2.4) and HT (19.3.2), ns-3's
  // OfdmPhy::GetSignalExtension; else 0.
  TimeNs signal_extension_ns = 0;
  PhyMode header_mode;
  int header_bits = 0;
};
PhyHeader HeaderFor(Standard standard, const PhyMode& mode, bool short_preamble);

// Exact PPDU duration of `psdu_bytes` in `mode` with `header`.
TimeNs PpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes);

// HT/VHT: ns-3 3.37's duration of one MPDU of `psdu_bytes` inside an A-MPDU as
// MinstrelHtWifiManager::CalculateMpduTxDuration computes it: the preamble and header, then
// fractional symbols (HtPhy::GetPayloadDuration, truncated to the ns): the first MPDU carries
// the SERVICE and tail bits (16 + 8 L + 6 N_ES bits), a middle one 8 L bits only. No signal
// extension. Minstrel-HT's per-rate "perfect" times.
TimeNs AmpduMpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes,
                           bool first_in_ampdu);

// Control responses (ACK, CTS) and, here, RTS use the highest basic rate not
// above the rate of the frame they answer (10.6.6.5.2), of an allowed
// modulation class. The basic rate set is ns-3 3.37's for an ad hoc network:
// every mandatory rate of the PHY (AdhocWifiMac adds them all through
// WifiRemoteStationManager::AddAllSupportedModes): 11a {6, 12, 24}; 11b
// {1, 2, 5.5, 11} (all four DSSS/HR-DSSS rates are mandatory, 16.1.1), so an
// 11b ACK goes at the data rate; 11g {1, 2, 5.5, 11, 6, 12, 24}, and an ERP-OFDM
// frame is answered at 6, 12 or 24, a DSSS frame at its own rate.
double ControlRateFor(Standard standard, double rate_mbps);
// The same for any data mode. HT/VHT: ns-3 3.37's GetControlAnswerMode compares modulation and
// code rate (WifiMode::IsHigherDataRate), which gives the basic rate at or below the MCS's non-HT
// reference rate (BPSK 1/2: 6; QPSK: 12; 16-QAM and up: 24), at 2.4 as at 5 GHz.
double ControlRateFor(Standard standard, const PhyMode& mode);
// Lowest basic rate: group-addressed frames go at it by default (ns-3's
// GetNonUnicastMode: the first basic mode), and EIFS uses an ACK at it.
// 11a: 6 Mb/s; 11b and 11g: 1 Mb/s DSSS (ns-3's 11g PHY includes the DSSS
// rates, and its EIFS uses a 304 us ACK, WifiPhy::Configure80211g).
double LowestBasicRate(Standard standard);

// Frame sizes on air (bytes, FCS included).
inline constexpr int kMacHeaderBytes = 24;
inline constexpr int kQosControlBytes = 2;  // QoS Data frames: a 26-byte header (9.2.4.5).
inline constexpr int kLlcSnapBytes = 8;
inline constexpr int kFcsBytes = 4;
inline constexpr int kAckBytes = 14;
inline constexpr int kCtsBytes = 14;
inline constexpr int kRtsBytes = 20;
inline constexpr int kCfEndBytes = 20;  // 9.3.1.9: FC, Duration, RA, BSSID (TA), FCS.
inline constexpr int kEthernetHeaderBytes = 14;
inline constexpr int kMaxMsduBytes = 2304;  // 9.2.4.7.1
// An Ethernet II frame of E bytes becomes an MPDU of E + 22 bytes.
// A VHT PPDU always carries an A-MPDU (21.10.3): one MPDU alone is an S-MPDU behind a 4-byte
// delimiter (ns-3 3.37: VhtFrameExchangeManager::GetWifiPsdu, WifiPsdu's single-MPDU size).
inline constexpr int kMpduDelimiterBytes = 4;
// As a QoS Data frame (n/ac stations), 24 bytes.
inline constexpr int MpduBytesForEthernet(int ethernet_bytes, bool qos = false) {
  return ethernet_bytes - kEthernetHeaderBytes + kMacHeaderBytes + (qos ? kQosControlBytes : 0) +
         kLlcSnapBytes + kFcsBytes;
}


}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_PHY_MODE_H_

#include "mac_phy_sim/phy_mode.h"

#include <cmath>
#include <optional>
#include <string>

namespace sitlnet::mac {
namespace {

bool SameRate(double a, double b) { return std::fabs(a - b) < 1e-9; }

std::string RateList(Standard standard) {
  switch (standard) {
    case Standard::k80211b:
      return "1, 2, 5.5, 11";
    case Standard::k80211g:
      return "1, 2, 5.5, 11, 6, 9, 12, 18, 24, 36, 48, 54";
    default:
      return "6, 9, 12, 18, 24, 36, 48, 54";
  }
}

// The DSSS/HR-DSSS mode of `rate_mbps` (clauses 15, 16), if it is one.
std::optional<PhyMode> DsssMode(double rate_mbps) {
  if (SameRate(rate_mbps, 1)) return PhyMode{1, Modulation::kDbpsk, 0, false};
  if (SameRate(rate_mbps, 2)) return PhyMode{2, Modulation::kDqpsk, 0, false};
  if (SameRate(rate_mbps, 5.5)) return PhyMode{5.5, Modulation::kCck55, 0, false};
  if (SameRate(rate_mbps, 11)) return PhyMode{11, Modulation::kCck11, 0, false};
  return std::nullopt;
}

// N_DBPS of an OFDM rate (Table 17-4): 4 data bits per symbol per Mb/s.
int DataBitsPerSymbol(double rate_mbps) { return static_cast<int>(std::lround(4 * rate_mbps)); }

}  // namespace

PhyMode ModeFor(Standard standard, double rate_mbps) {
  // 11b is DSSS/HR-DSSS only; an ERP (11g) PHY also has the DSSS rates (18.1.1).
  if (standard != Standard::k80211a) {
    if (const std::optional<PhyMode> dsss = DsssMode(rate_mbps)) return *dsss;
  }
  if (standard != Standard::k80211b) {
    // Table 17-4: modulation and coding rate of each OFDM rate.
    if (SameRate(rate_mbps, 6)) return {6, Modulation::kBpsk, 1, true};
    if (SameRate(rate_mbps, 9)) return {9, Modulation::kBpsk, 3, true};
    if (SameRate(rate_mbps, 12)) return {12, Modulation::kQpsk, 1, true};
    if (SameRate(rate_mbps, 18)) return {18, Modulation::kQpsk, 3, true};
    if (SameRate(rate_mbps, 24)) return {24, Modulation::kQam16, 1, true};
    if (SameRate(rate_mbps, 36)) return {36, Modulation::kQam16, 3, true};
    if (SameRate(rate_mbps, 48)) return {48, Modulation::kQam64, 2, true};
    if (SameRate(rate_mbps, 54)) return {54, Modulation::kQam64, 3, true};
  }
  throw Error("rate_mbps " + std::to_string(rate_mbps) + " is not a rate of this standard (" +
              RateList(standard) + ")");
}

PhyHeader HeaderFor(Standard standard, const PhyMode& mode, bool short_preamble) {
  PhyHeader header;
  if (mode.ofdm) {
    header.preamble_and_header_ns = 20 * kNsPerUs;  // 17.3.2: 16 us preamble + 4 us SIGNAL.
    header.signal_extension_ns = standard == Standard::k80211g ? 6 * kNsPerUs : 0;
    header.header_mode = ModeFor(Standard::k80211a, 6);
    header.header_bits = 24;
    return header;
  }
  const bool use_short = short_preamble && mode.rate_mbps > 2;  // ns-3: HR/DSSS only.
  header.preamble_and_header_ns = (use_short ? 96 : 192) * kNsPerUs;
  header.header_mode = *DsssMode(use_short ? 2 : 1);
  header.header_bits = 48;
  return header;
}

double ControlRateFor(Standard standard, double rate_mbps) {
  const PhyMode mode = ModeFor(standard, rate_mbps);  // Validates.
  if (!mode.ofdm) return rate_mbps;                   // Every DSSS/HR-DSSS rate is basic.
  if (rate_mbps >= 24) return 24;
  if (rate_mbps >= 12) return 12;
  return 6;
}

double LowestBasicRate(Standard standard) { return standard == Standard::k80211a ? 6 : 1; }

TimeNs PpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes) {
  if (!mode.ofdm) {
    // 15.4.4.2 / 16.3.4: LENGTH in microseconds, rounded up: 8*L/R with R in
    // Mb/s; for 5.5 Mb/s, 16*L/11.
    const int64_t numerator = 8LL * psdu_bytes * 10;
    const int64_t rate_x10 = std::lround(mode.rate_mbps * 10);
    const int64_t payload_us = (numerator + rate_x10 - 1) / rate_x10;
    return header.preamble_and_header_ns + payload_us * kNsPerUs;
  }
  // 17.4.3: 16 SERVICE bits + 8 L + 6 tail bits in 4 us symbols of N_DBPS bits.
  const int ndbps = DataBitsPerSymbol(mode.rate_mbps);
  const int64_t bits = 16 + 8LL * psdu_bytes + 6;
  const int64_t symbols = (bits + ndbps - 1) / ndbps;
  return header.preamble_and_header_ns + symbols * 4 * kNsPerUs + header.signal_extension_ns;
}

TimeNs PpduDurationNs(Standard standard, double rate_mbps, int psdu_bytes) {
  const PhyMode mode = ModeFor(standard, rate_mbps);
  return PpduDurationNs(mode, HeaderFor(standard, mode, /*short_preamble=*/false), psdu_bytes);
}

PhyInfo DerivePhyInfo(const MediumConfig& config) {
  auto demand = [](bool ok, const std::string& what) {
    if (!ok) throw Error("medium config: " + what);
  };
  ModeFor(config.standard, config.rate_mbps);
  demand(config.tx_power_dbm >= -30 && config.tx_power_dbm <= 40,
         "tx_power_dbm " + std::to_string(config.tx_power_dbm) + " out of range [-30, 40]");
  demand(config.noise_figure_db >= 0 && config.noise_figure_db <= 30,
         "noise_figure_db out of range [0, 30]");
  demand(config.path_loss_exponent > 0 && config.path_loss_exponent <= 10,
         "path_loss_exponent out of range (0, 10]");
  demand(!config.reference_loss_db || *config.reference_loss_db >= 0,
         "reference_loss_db must be >= 0");
  demand(config.shadowing_db_per_wall >= 0 && config.shadowing_db_per_m >= 0,
         "shadowing_db_per_wall and shadowing_db_per_m must be >= 0");
  demand(config.queue_limit_frames >= 1, "queue_limit_frames must be >= 1");
  demand(config.short_retry_limit >= 1 && config.long_retry_limit >= 1,
         "retry limits must be >= 1");
  demand(!config.capture_margin_db || *config.capture_margin_db >= 0,
         "capture_margin_db must be >= 0");

  PhyInfo info;
  const bool b = config.standard == Standard::k80211b;
  const bool a = config.standard == Standard::k80211a;
  info.frequency_mhz = a ? 5180 : 2412;  // Channel 36 / channel 1.
  // Thermal noise kTB at 290 K (k = 1.3803e-23 J/K as ns-3 uses) over 20 MHz
  // (OFDM) or 22 MHz (DSSS), plus the noise figure: -93.97 dBm for 11a.
  const double bandwidth_hz = b ? 22e6 : 20e6;
  info.noise_floor_dbm =
      10 * std::log10(1.3803e-23 * 290 * bandwidth_hz * 1000) + config.noise_figure_db;
  // Friis at 1 m, c = 3e8 m/s: 46.6777 dB at 5.15 GHz (ns-3's default
  // reference loss for 11a), 40.046 dB at 2.4 GHz.
  const double friis_hz = a ? 5.15e9 : 2.4e9;
  info.reference_loss_db =
      config.reference_loss_db.value_or(20 * std::log10(4 * M_PI * friis_hz / 3e8));
  info.ack_rate_mbps = ControlRateFor(config.standard, config.rate_mbps);
  info.group_rate_mbps = config.group_rate_mbps.value_or(LowestBasicRate(config.standard));
  try {
    ModeFor(config.standard, info.group_rate_mbps);
  } catch (const Error& e) {
    throw Error(std::string("medium config: group_") + e.what());
  }
  demand(config.queue_max_delay_ns >= 0, "queue_max_delay_ns must be >= 0");
  demand(!config.nakagami_fading ||
             (config.nakagami_m0 >= 0.5 && config.nakagami_m1 >= 0.5 && config.nakagami_m2 >= 0.5),
         "nakagami_m0/m1/m2 must be >= 0.5 (Nakagami's m)");
  demand(config.nakagami_d1_m > 0 && config.nakagami_d2_m >= config.nakagami_d1_m,
         "need 0 < nakagami_d1_m <= nakagami_d2_m");
  demand(config.lognormal_shadowing_sigma_db >= 0 && config.lognormal_shadowing_sigma_db <= 30,
         "lognormal_shadowing_sigma_db out of range [0, 30]");
  // aSlotTime, aSIFSTime: 17.4.4 (OFDM), 15.4.5 (DSSS), 18.4.5 (ERP).
  const int slot_us = a ? 9 : (b ? 20 : (config.short_slot ? 9 : 20));
  const int sifs_us = a ? 16 : 10;
  info.slot_ns = slot_us * kNsPerUs;
  info.sifs_ns = sifs_us * kNsPerUs;
  info.difs_ns = info.sifs_ns + 2 * info.slot_ns;  // 10.3.2.3.5
  // EIFS = aSIFSTime + ACK at the lowest basic rate + DIFS (10.3.2.3.7,
  // Table 10-5): 44 us ACK for 11a, 304 us for 11b and 11g (ns-3's
  // WifiPhy::GetAckTxTime; its 11g PHY is configured on top of the 11b one).
  info.eifs_ns = info.sifs_ns +
                 PpduDurationNs(config.standard, LowestBasicRate(config.standard), kAckBytes) +
                 info.difs_ns;
  info.cw_min = config.cw_min.value_or(b ? 31 : 15);
  info.cw_max = config.cw_max.value_or(1023);
  demand(info.cw_min >= 0 && info.cw_max >= info.cw_min && info.cw_max <= 65535,
         "need 0 <= cw_min <= cw_max <= 65535");
  return info;
}

}  // namespace sitlnet::mac

#include "mac_phy_sim/phy_mode.h"

#include <cmath>
#include <string>

namespace sitlnet::mac {
namespace {

bool SameRate(double a, double b) { return std::fabs(a - b) < 1e-9; }

std::string RateList(Standard standard) {
  return standard == Standard::k80211b ? "1, 2, 5.5, 11" : "6, 9, 12, 18, 24, 36, 48, 54";
}

// N_DBPS of an OFDM rate (Table 17-4): 4 data bits per symbol per Mb/s.
int DataBitsPerSymbol(double rate_mbps) { return static_cast<int>(std::lround(4 * rate_mbps)); }

}  // namespace

PhyMode ModeFor(Standard standard, double rate_mbps) {
  if (standard == Standard::k80211b) {
    // Clause 15 (1, 2 Mb/s) and 16 (5.5, 11 Mb/s CCK).
    if (SameRate(rate_mbps, 1)) return {1, Modulation::kDbpsk, 0, false};
    if (SameRate(rate_mbps, 2)) return {2, Modulation::kDqpsk, 0, false};
    if (SameRate(rate_mbps, 5.5)) return {5.5, Modulation::kCck55, 0, false};
    if (SameRate(rate_mbps, 11)) return {11, Modulation::kCck11, 0, false};
  } else {
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

PhyMode HeaderModeFor(Standard standard) {
  return standard == Standard::k80211b ? ModeFor(standard, 1) : ModeFor(standard, 6);
}

int HeaderBits(Standard standard) { return standard == Standard::k80211b ? 48 : 24; }

TimeNs PreambleAndHeaderNs(Standard standard) {
  // 17.3.2: 16 us preamble + 4 us SIGNAL; 15.3.3: 144 us long preamble + 48 us header.
  return (standard == Standard::k80211b ? 192 : 20) * kNsPerUs;
}

TimeNs SignalExtensionNs(Standard standard) {
  return standard == Standard::k80211g ? 6 * kNsPerUs : 0;
}

double ControlRateFor(Standard standard, double rate_mbps) {
  ModeFor(standard, rate_mbps);  // Validates.
  if (standard == Standard::k80211b) return rate_mbps >= 2 ? 2 : 1;
  if (rate_mbps >= 24) return 24;
  if (rate_mbps >= 12) return 12;
  return 6;
}

double LowestBasicRate(Standard standard) { return standard == Standard::k80211b ? 1 : 6; }

TimeNs PpduDurationNs(Standard standard, double rate_mbps, int psdu_bytes) {
  const PhyMode mode = ModeFor(standard, rate_mbps);
  if (!mode.ofdm) {
    // 15.4.4.2 / 16.3.4: LENGTH in microseconds, rounded up; long preamble.
    // 8*L/R with R in Mb/s; for 5.5 Mb/s, 16*L/11.
    const int64_t numerator = 8LL * psdu_bytes * 10;
    const int64_t rate_x10 = std::lround(rate_mbps * 10);
    const int64_t payload_us = (numerator + rate_x10 - 1) / rate_x10;
    return PreambleAndHeaderNs(standard) + payload_us * kNsPerUs;
  }
  // 17.4.3: 16 SERVICE bits + 8 L + 6 tail bits in 4 us symbols of N_DBPS bits.
  const int ndbps = DataBitsPerSymbol(rate_mbps);
  const int64_t bits = 16 + 8LL * psdu_bytes + 6;
  const int64_t symbols = (bits + ndbps - 1) / ndbps;
  return PreambleAndHeaderNs(standard) + symbols * 4 * kNsPerUs + SignalExtensionNs(standard);
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
  // aSlotTime, aSIFSTime: 17.4.4 (OFDM), 15.4.5 (DSSS), 18.4.5 (ERP).
  const int slot_us = a ? 9 : (b ? 20 : (config.short_slot ? 9 : 20));
  const int sifs_us = a ? 16 : 10;
  info.slot_ns = slot_us * kNsPerUs;
  info.sifs_ns = sifs_us * kNsPerUs;
  info.difs_ns = info.sifs_ns + 2 * info.slot_ns;  // 10.3.2.3.5
  // EIFS = aSIFSTime + ACK at the lowest basic rate + DIFS (10.3.2.3.7).
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

#include "mac_phy_sim/phy_mode.h"

#include <cmath>
#include <sstream>
#include <string>

namespace sitlnet::mac {
namespace {

bool SameRate(double a, double b) { return std::fabs(a - b) < 1e-9; }

// Every data rate's mode, the one table of them (validation reads it through RatesMbps too).
// DSSS/HR-DSSS (clauses 15, 16) first, then OFDM with Table 17-4's modulation and coding rate:
// an ERP (11g) PHY tries them in this order, as ModeFor always has.
constexpr PhyMode kModes[] = {
    {1, Modulation::kDbpsk, 0, false},   {2, Modulation::kDqpsk, 0, false},
    {5.5, Modulation::kCck55, 0, false}, {11, Modulation::kCck11, 0, false},
    {6, Modulation::kBpsk, 1, true},     {9, Modulation::kBpsk, 3, true},
    {12, Modulation::kQpsk, 1, true},    {18, Modulation::kQpsk, 3, true},
    {24, Modulation::kQam16, 1, true},   {36, Modulation::kQam16, 3, true},
    {48, Modulation::kQam64, 2, true},   {54, Modulation::kQam64, 3, true},
};

// 11a is OFDM only, 11b DSSS/HR-DSSS only; an ERP (11g) PHY also has the DSSS rates (18.1.1).
bool StandardHas(Standard standard, const PhyMode& mode) {
  return mode.ofdm ? standard != Standard::k80211b : standard != Standard::k80211a;
}

// The entry of `rate_mbps` in `standard`, or null.
const PhyMode* FindMode(Standard standard, double rate_mbps) {
  for (const PhyMode& mode : kModes) {
    if (StandardHas(standard, mode) && SameRate(mode.rate_mbps, rate_mbps)) return &mode;
  }
  return nullptr;
}

std::string RateList(Standard standard) {
  std::ostringstream text;
  for (double rate : RatesMbps(standard)) text << (text.tellp() > 0 ? ", " : "") << rate;
  return text.str();
}

// N_DBPS of an OFDM rate (Table 17-4): 4 data bits per symbol per Mb/s.
int DataBitsPerSymbol(double rate_mbps) { return static_cast<int>(std::lround(4 * rate_mbps)); }

}  // namespace

std::vector<double> RatesMbps(Standard standard) {
  std::vector<double> rates;
  for (const PhyMode& mode : kModes) {
    if (StandardHas(standard, mode)) rates.push_back(mode.rate_mbps);
  }
  return rates;
}

bool HasRate(Standard standard, double rate_mbps) {
  return FindMode(standard, rate_mbps) != nullptr;
}

PhyMode ModeFor(Standard standard, double rate_mbps) {
  if (const PhyMode* mode = FindMode(standard, rate_mbps)) return *mode;
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
  header.header_mode = ModeFor(Standard::k80211b, use_short ? 2 : 1);
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
  // The scenario's field options declare and check the ranges of what follows (docs/scenario.md);
  // here only what the formulas need is asserted, so the two can never disagree again.
  SITLNET_DEMAND(std::isfinite(config.tx_power_dbm));
  SITLNET_DEMAND(std::isfinite(config.noise_figure_db));
  SITLNET_DEMAND(config.path_loss_exponent > 0 && std::isfinite(config.path_loss_exponent));
  SITLNET_DEMAND(!config.reference_loss_db || *config.reference_loss_db >= 0);
  SITLNET_DEMAND(config.shadowing_db_per_wall >= 0 && config.shadowing_db_per_m >= 0);
  SITLNET_DEMAND(!config.path_loss_frequency_hz ||
                 (*config.path_loss_frequency_hz >= 0.5e9 && *config.path_loss_frequency_hz <= 100e9));
  SITLNET_DEMAND(config.two_ray_system_loss > 0 && config.two_ray_min_distance_m >= 0);
  SITLNET_DEMAND(config.v2v_truck_percent >= 0 && config.v2v_truck_percent <= 100);
  SITLNET_DEMAND(config.queue_limit_frames >= 1);
  SITLNET_DEMAND(!config.capture_margin_db || *config.capture_margin_db >= 0);
  demand(config.short_retry_limit >= 1 && config.long_retry_limit >= 1,
         "retry limits must be >= 1");

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
  info.path_loss_frequency_hz = config.path_loss_frequency_hz.value_or(friis_hz);
  info.ack_rate_mbps = ControlRateFor(config.standard, config.rate_mbps);
  info.group_rate_mbps = config.group_rate_mbps.value_or(LowestBasicRate(config.standard));
  try {
    ModeFor(config.standard, info.group_rate_mbps);
  } catch (const Error& e) {
    throw Error(std::string("medium config: group_") + e.what());
  }
  SITLNET_DEMAND(config.queue_max_delay_ns >= 0);
  // Nakagami's m >= 0.5 (the Gamma draw's shape); d1 <= d2 orders the distance bands.
  SITLNET_DEMAND(
      !config.nakagami_fading ||
      (config.nakagami_m0 >= 0.5 && config.nakagami_m1 >= 0.5 && config.nakagami_m2 >= 0.5));
  SITLNET_DEMAND(config.nakagami_d1_m > 0 && config.nakagami_d2_m >= config.nakagami_d1_m);
  SITLNET_DEMAND(config.lognormal_shadowing_sigma_db >= 0);
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

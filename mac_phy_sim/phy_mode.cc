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

// The legacy PHY under a standard: n at 2.4 GHz runs on an ERP (11g) PHY, n at 5 GHz and ac on
// an OFDM (11a) PHY (ns-3 3.37's WifiPhy::Configure80211n / Configure80211ac).
Standard LegacyBase(Standard standard) {
  switch (standard) {
    case Standard::k80211n2_4GHz:
      return Standard::k80211g;
    case Standard::k80211n5GHz:
    case Standard::k80211ac:
      return Standard::k80211a;
    default:
      return standard;
  }
}

// 11a is OFDM only, 11b DSSS/HR-DSSS only; an ERP (11g) PHY also has the DSSS rates (18.1.1).
bool StandardHas(Standard standard, const PhyMode& mode) {
  standard = LegacyBase(standard);
  return mode.ofdm ? standard != Standard::k80211b : standard != Standard::k80211a;
}

// The per-stream MCSs of HT (Tables 19-27..) and VHT (Tables 21-30..): modulation, bits per
// subcarrier, code rate. HT uses 0-7; VHT adds 256-QAM (8, 9).
struct McsRow {
  Modulation modulation;
  int bits_per_subcarrier;
  int code_rate_b;
  int rate_numerator, rate_denominator;
};
constexpr McsRow kMcsRows[] = {
    {Modulation::kBpsk, 1, 1, 1, 2},   {Modulation::kQpsk, 2, 1, 1, 2},
    {Modulation::kQpsk, 2, 3, 3, 4},   {Modulation::kQam16, 4, 1, 1, 2},
    {Modulation::kQam16, 4, 3, 3, 4},  {Modulation::kQam64, 6, 2, 2, 3},
    {Modulation::kQam64, 6, 3, 3, 4},  {Modulation::kQam64, 6, 5, 5, 6},
    {Modulation::kQam256, 8, 3, 3, 4}, {Modulation::kQam256, 8, 5, 5, 6},
};

// The row of an HT or VHT mode (HT's index counts streams: 8 per stream).
const McsRow& RowOf(const PhyMode& mode) {
  return kMcsRows[mode.format == PhyFormat::kHt ? mode.mcs % 8 : mode.mcs];
}

// N_SD: data subcarriers at a width (19.3.7, 21.3.7).
int DataSubcarriers(int channel_width_mhz) {
  return channel_width_mhz == 80 ? 234 : (channel_width_mhz == 40 ? 108 : 52);
}

// N_DBPS of an HT/VHT mode, 0 when it is not a whole number (VHT MCS 9 at 20 MHz, 1-2 streams:
// the reason the standard excludes it).
int64_t McsDataBitsPerSymbol(const PhyMode& mode) {
  const McsRow& row = RowOf(mode);
  const int64_t coded = int64_t{DataSubcarriers(mode.channel_width_mhz)} *
                        row.bits_per_subcarrier * mode.spatial_streams * row.rate_numerator;
  return coded % row.rate_denominator == 0 ? coded / row.rate_denominator : 0;
}

TimeNs McsSymbolNs(const PhyMode& mode) { return mode.short_guard_interval ? 3600 : 4000; }

// N_ES, the BCC encoders: ns-3 3.37 adds one per 320 (HT) or 540 (VHT) Mb/s, 350 or 600 with
// the short GI (HtPhy/VhtPhy::GetNumberBccEncoders; its exceptions need 3+ streams or 160 MHz).
int64_t BccEncoders(const PhyMode& mode) {
  const int64_t per_encoder_mbps = mode.format == PhyFormat::kHt
                                       ? (mode.short_guard_interval ? 350 : 320)
                                       : (mode.short_guard_interval ? 600 : 540);
  // ceil(rate / per_encoder), rate = N_DBPS x 1000 / symbol_ns Mb/s, in integers.
  const int64_t denominator = per_encoder_mbps * McsSymbolNs(mode);
  return (McsDataBitsPerSymbol(mode) * 1000 + denominator - 1) / denominator;
}

// 6 us signal extension for OFDM-based PPDUs on a 2.4 GHz PHY.
bool HasSignalExtension(Standard standard) { return LegacyBase(standard) == Standard::k80211g; }

bool IsFiveGhz(Standard standard) { return LegacyBase(standard) == Standard::k80211a; }

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

bool IsHtOrVht(Standard standard) { return LegacyBase(standard) != standard; }

PhyMode McsModeFor(Standard standard, int mcs, int spatial_streams, int channel_width_mhz,
                   bool short_guard_interval) {
  const bool vht = standard == Standard::k80211ac;
  if (!IsHtOrVht(standard)) throw Error("mcs needs standard 802.11n or 802.11ac");
  if (vht ? (mcs < 0 || mcs > 9) : (mcs < 0 || mcs > 15)) {
    throw Error("mcs " + std::to_string(mcs) +
                (vht ? " out of range [0, 9] for 802.11ac"
                     : " out of range [0, 15] for 802.11n (8-15: two spatial streams)"));
  }
  if (spatial_streams < 1 || spatial_streams > 2) {
    throw Error("spatial_streams " + std::to_string(spatial_streams) + " out of range [1, 2]");
  }
  if (!vht && spatial_streams != mcs / 8 + 1) {
    throw Error("spatial_streams " + std::to_string(spatial_streams) + " does not match HT mcs " +
                std::to_string(mcs) + " (" + std::to_string(mcs / 8 + 1) +
                " stream(s): 802.11n MCS 0-7 use one, 8-15 two)");
  }
  const bool width_ok = channel_width_mhz == 20 || channel_width_mhz == 40 ||
                        (vht && channel_width_mhz == 80);
  if (!width_ok) {
    throw Error("channel_width_mhz " + std::to_string(channel_width_mhz) + " is not a width of " +
                (vht ? "802.11ac (20, 40, 80)" : "802.11n (20, 40)"));
  }
  PhyMode mode;
  mode.format = vht ? PhyFormat::kVht : PhyFormat::kHt;
  mode.mcs = mcs;
  mode.spatial_streams = spatial_streams;
  mode.channel_width_mhz = channel_width_mhz;
  mode.short_guard_interval = short_guard_interval;
  const McsRow& row = RowOf(mode);
  mode.modulation = row.modulation;
  mode.code_rate_b = row.code_rate_b;
  const int64_t ndbps = McsDataBitsPerSymbol(mode);
  if (ndbps == 0) {
    throw Error("VHT mcs " + std::to_string(mcs) + " is not valid at " +
                std::to_string(channel_width_mhz) + " MHz with " +
                std::to_string(spatial_streams) + " spatial stream(s) (21.5)");
  }
  mode.rate_mbps = static_cast<double>(ndbps) * 1000.0 / static_cast<double>(McsSymbolNs(mode));
  return mode;
}

PhyMode DataModeFor(const MediumConfig& config, const StationRadio& radio) {
  if (!IsHtOrVht(config.standard)) {
    return ModeFor(config.standard, radio.rate_mbps.value_or(config.rate_mbps));
  }
  const int mcs = radio.mcs.value_or(config.mcs);
  const bool vht = config.standard == Standard::k80211ac;
  const int streams = config.spatial_streams.value_or(vht ? 1 : mcs / 8 + 1);
  return McsModeFor(config.standard, mcs, streams, config.channel_width_mhz.value_or(vht ? 80 : 20),
                    config.short_guard_interval);
}

int MeasurementWidthMhz(const PhyMode& mode) {
  if (mode.format != PhyFormat::kLegacy) return mode.channel_width_mhz;
  return mode.ofdm ? 20 : 22;
}

double NoiseFloorDbm(double bandwidth_hz, double noise_figure_db) {
  return 10 * std::log10(1.3803e-23 * 290 * bandwidth_hz * 1000) + noise_figure_db;
}

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
  if (mode.format != PhyFormat::kLegacy) {
    // L-STF + L-LTF, L-SIG, HT-SIG or VHT-SIG-A, HT-STF or VHT-STF, one LTF per stream.
    header.preamble_and_header_ns = (16 + 4 + 8 + 4 + 4 * mode.spatial_streams) * kNsPerUs;
    header.signal_extension_ns = HasSignalExtension(standard) ? 6 * kNsPerUs : 0;
    header.header_mode = ModeFor(Standard::k80211a, 6);
    header.header_bits = 24 + 48;  // L-SIG, HT-SIG / VHT-SIG-A.
    return header;
  }
  if (mode.ofdm) {
    header.preamble_and_header_ns = 20 * kNsPerUs;  // 17.3.2: 16 us preamble + 4 us SIGNAL.
    header.signal_extension_ns = HasSignalExtension(standard) ? 6 * kNsPerUs : 0;
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

double ControlRateFor(Standard standard, const PhyMode& mode) {
  if (mode.format == PhyFormat::kLegacy) return ControlRateFor(standard, mode.rate_mbps);
  switch (mode.modulation) {
    case Modulation::kBpsk:
      return 6;
    case Modulation::kQpsk:
      return 12;
    default:
      return 24;
  }
}

double LowestBasicRate(Standard standard) { return IsFiveGhz(standard) ? 6 : 1; }

TimeNs PpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes) {
  if (mode.format != PhyFormat::kLegacy) {
    // 19.3.11.1 / 21.4.3: 16 SERVICE bits + 8 L + 6 tail bits per encoder, whole symbols (BCC,
    // no STBC), as ns-3's HtPhy::GetPayloadDuration.
    const int64_t ndbps = McsDataBitsPerSymbol(mode);
    const int64_t bits = 16 + 8LL * psdu_bytes + 6 * BccEncoders(mode);
    const int64_t symbols = (bits + ndbps - 1) / ndbps;
    return header.preamble_and_header_ns + symbols * McsSymbolNs(mode) +
           header.signal_extension_ns;
  }
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

TimeNs AmpduMpduDurationNs(const PhyMode& mode, const PhyHeader& header, int psdu_bytes,
                           bool first_in_ampdu) {
  SITLNET_DEMAND(mode.format != PhyFormat::kLegacy);
  const int64_t bits =
      8LL * psdu_bytes + (first_in_ampdu ? 16 + 6 * BccEncoders(mode) : 0);
  // bits / N_DBPS symbols of symbol_ns each, exactly, then truncated (ns-3 keeps femtoseconds
  // and its Time truncates them to its nanosecond resolution).
  return header.preamble_and_header_ns + bits * McsSymbolNs(mode) / McsDataBitsPerSymbol(mode);
}

TimeNs PpduDurationNs(Standard standard, double rate_mbps, int psdu_bytes) {
  const PhyMode mode = ModeFor(standard, rate_mbps);
  return PpduDurationNs(mode, HeaderFor(standard, mode, /*short_preamble=*/false), psdu_bytes);
}

PhyInfo DerivePhyInfo(const MediumConfig& config) {
  auto demand = [](bool ok, const std::string& what) {
    if (!ok) throw Error("medium config: " + what);
  };
  const PhyMode data_mode = DataModeFor(config, StationRadio{});
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
  SITLNET_DEMAND(config.v2v_update_period_ns >= 0);
  SITLNET_DEMAND(config.queue_limit_frames >= 1);
  SITLNET_DEMAND(!config.capture_margin_db || *config.capture_margin_db >= 0);
  demand(config.short_retry_limit >= 1 && config.long_retry_limit >= 1,
         "retry limits must be >= 1");

  const bool ht = IsHtOrVht(config.standard);
  demand(!ht || config.rate_control != MediumConfig::RateControl::kIdeal,
         "rate_control ideal is modelled for 802.11a/b/g only");
  const MediumConfig::Minstrel& minstrel = config.minstrel;
  demand(minstrel.update_stats_ns > 0 && minstrel.ht_update_stats_ns > 0 &&
             minstrel.look_around_percent >= 0 &&
             minstrel.look_around_percent <= 100 && minstrel.ewma_percent >= 0 &&
             minstrel.ewma_percent <= 100 && minstrel.sample_columns >= 1 &&
             minstrel.packet_bytes >= 1,
         "minstrel parameters out of range");
  PhyInfo info;
  const bool b = config.standard == Standard::k80211b;
  const bool a = IsFiveGhz(config.standard);
  // Channel 36 / channel 1 (the primary 20 MHz channel of a wider n/ac channel).
  info.frequency_mhz = a ? 5180 : 2412;
  // Thermal noise kTB at 290 K (k = 1.3803e-23 J/K as ns-3 uses) over 20 MHz
  // (OFDM) or 22 MHz (DSSS), plus the noise figure: -93.97 dBm for 11a. n/ac:
  // over the data width (ns-3's InterferenceHelper::CalculateSnr).
  const double bandwidth_hz = ht ? MeasurementWidthMhz(data_mode) * 1e6 : (b ? 22e6 : 20e6);
  info.noise_floor_dbm = NoiseFloorDbm(bandwidth_hz, config.noise_figure_db);
  // Friis at 1 m, c = 3e8 m/s: 46.6777 dB at 5.15 GHz (ns-3's default
  // reference loss for 11a), 40.046 dB at 2.4 GHz.
  const double friis_hz = a ? 5.15e9 : 2.4e9;
  info.reference_loss_db =
      config.reference_loss_db.value_or(20 * std::log10(4 * M_PI * friis_hz / 3e8));
  info.path_loss_frequency_hz = config.path_loss_frequency_hz.value_or(friis_hz);
  info.ack_rate_mbps = ControlRateFor(config.standard, data_mode);
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
  SITLNET_DEMAND(config.jakes_doppler_hz > 0 && config.jakes_doppler_hz <= 1e4);
  SITLNET_DEMAND(config.jakes_oscillators >= 4 && config.jakes_oscillators <= 1000);
  // Both model the same multipath fading: chained, they would fade each frame twice.
  demand(!(config.jakes_fading && config.nakagami_fading),
         "jakes_fading and nakagami_fading both model fast fading: set one");
  demand(config.jakes_fading || !config.jakes_doppler_from_speed,
         "jakes_doppler_from_speed needs jakes_fading");
  // aSlotTime, aSIFSTime: 17.4.4 (OFDM), 15.4.5 (DSSS), 18.4.5 (ERP).
  const int slot_us = a ? 9 : (b ? 20 : (config.short_slot ? 9 : 20));
  const int sifs_us = a ? 16 : 10;
  info.slot_ns = slot_us * kNsPerUs;
  info.sifs_ns = sifs_us * kNsPerUs;
  info.difs_ns = info.sifs_ns + 2 * info.slot_ns;  // 10.3.2.3.5
  // EIFS = aSIFSTime + ACK at the lowest basic rate + DIFS (10.3.2.3.7,
  // Table 10-5): 44 us ACK for 11a, 304 us for 11b and 11g (ns-3's
  // WifiPhy::GetAckTxTime; its 11g PHY is configured on top of the 11b one).
  // QoS stations (n/ac): AC_BE's AIFS instead of DIFS, here and in EIFS (ns-3's
  // ChannelAccessManager: EIFS - DIFS, then AIFS).
  // aCWmin, aCWmax: 31/1023 DSSS (15.4.5), 15/1023 OFDM and ERP (ns-3's 11g, as its DCF).
  const int a_cw_min = b ? 31 : 15, a_cw_max = 1023;
  info.qos = ht || config.qos;
  for (int ac = 0; ac < kAccessCategoryCount; ++ac) {
    info.edca[ac] = DefaultEdcaParameters(static_cast<AccessCategory>(ac), a_cw_min, a_cw_max, b);
  }
  EdcaParameters& best_effort = info.edca[static_cast<int>(AccessCategory::kBestEffort)];
  if (!info.qos) best_effort = EdcaParameters{2, a_cw_min, a_cw_max, 0};  // The DCF.
  best_effort.cw_min = config.cw_min.value_or(best_effort.cw_min);
  best_effort.cw_max = config.cw_max.value_or(best_effort.cw_max);
  info.aifsn = best_effort.aifsn;
  info.aifs_ns = info.sifs_ns + info.aifsn * info.slot_ns;
  info.eifs_ns = info.sifs_ns +
                 PpduDurationNs(config.standard, LowestBasicRate(config.standard), kAckBytes) +
                 info.aifs_ns;
  info.cw_min = best_effort.cw_min;
  info.cw_max = best_effort.cw_max;
  demand(info.cw_min >= 0 && info.cw_max >= info.cw_min && info.cw_max <= 65535,
         "need 0 <= cw_min <= cw_max <= 65535");
  return info;
}

}  // namespace sitlnet::mac

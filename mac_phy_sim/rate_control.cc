// Rate selection: the table of rates of the standard with their control
// responses, the per-station constant rate, and ns-3 3.37's IdealWifiManager
// (per destination, the highest rate whose SNR threshold for ideal_ber is
// below the SNR the destination last measured on an acknowledged frame of
// ours; RTS at the highest basic rate whose threshold is below it).
#include <cmath>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

// ns-3 ErrorRateModel::CalculateSnr: the SNR (linear) at which one bit fails
// with probability `ber`, by bisection over [1e-25, 1e25] down to 2e-12 (at
// most 200 halvings: far above the threshold the spacing of doubles is wider
// than 2e-12, so ns-3's loop would not end there).
double SnrForBer(MediumConfig::ErrorModel model, const PhyMode& mode, double ber) {
  double low = 1e-25, high = 1e25;
  for (int i = 0; i < 200 && high - low > 2e-12; ++i) {
    const double middle = low + (high - low) / 2;
    if (1 - ChunkSuccessRate(model, mode, middle, 1) > ber) {
      low = middle;
    } else {
      high = middle;
    }
  }
  return low;
}

ModeEntry MakeMode(const State& s, const PhyMode& mode) {
  const MediumConfig& config = s.config;
  const PhyHeader header = HeaderFor(config.standard, mode, config.short_preamble);
  const double noise_mw =
      IsHtOrVht(config.standard)
          ? std::pow(10.0, NoiseFloorDbm(MeasurementWidthMhz(mode) * 1e6, config.noise_figure_db) / 10)
          : s.noise_mw;
  return ModeEntry{mode, PerfectSinr(config.error_model, mode), header,
                   PerfectSinr(config.error_model, header.header_mode), noise_mw};
}

bool SameMode(const PhyMode& a, const PhyMode& b) {
  return std::fabs(a.rate_mbps - b.rate_mbps) < 1e-9 && a.format == b.format && a.mcs == b.mcs &&
         a.spatial_streams == b.spatial_streams;
}

// The entry of a data mode: its control responses, their airtimes, Ideal's threshold.
RateEntry MakeRate(const State& s, const PhyMode& mode) {
  RateEntry entry;
  entry.data = MakeMode(s, mode);
  entry.control = MakeMode(s, ModeFor(s.config.standard, ControlRateFor(s.config.standard, mode)));
  entry.ack_ns = PpduDurationNs(entry.control.mode, entry.control.header, kAckBytes);
  entry.cts_ns = PpduDurationNs(entry.control.mode, entry.control.header, kCtsBytes);
  if (s.config.rate_control == MediumConfig::RateControl::kIdeal) {
    entry.ideal_snr_threshold = SnrForBer(s.config.error_model, entry.data.mode, s.config.ideal_ber);
  }
  entry.basic = mode.format == PhyFormat::kLegacy &&
                ControlRateFor(s.config.standard, mode.rate_mbps) == mode.rate_mbps;
  return entry;
}

double LastSnr(const StationState& st, const MacAddress& destination) {
  for (const auto& [mac, snr] : st.ideal_snr) {
    if (mac == destination) return snr;
  }
  return 0;  // ns-3: m_lastSnrObserved starts at 0, so the lowest rate.
}

}  // namespace

void BuildRates(State& s) {
  static constexpr double kAll[] = {1, 2, 5.5, 6, 9, 11, 12, 18, 24, 36, 48, 54};
  for (double rate : kAll) {
    if (!HasRate(s.config.standard, rate)) continue;  // n/ac: the legacy PHY's rates.
    s.rates.push_back(MakeRate(s, ModeFor(s.config.standard, rate)));
  }
  if (IsHtOrVht(s.config.standard)) {
    // Every MCS a station may use with the config's width and guard interval (stations may
    // override the MCS; HT's index carries the streams, VHT's does not).
    const PhyMode data = DataModeFor(s.config, StationRadio{});
    const bool vht = data.format == PhyFormat::kVht;
    for (int mcs = 0; mcs < (vht ? 10 : 16); ++mcs) {
      for (int streams = 1; streams <= 2; ++streams) {
        if (!vht && streams != mcs / 8 + 1) continue;
        try {
          s.rates.push_back(MakeRate(s, McsModeFor(s.config.standard, mcs, streams,
                                                   data.channel_width_mhz,
                                                   data.short_guard_interval)));
        } catch (const Error&) {
          // VHT MCS 9 at 20 MHz: no such mode.
        }
      }
    }
  }
  s.group_rate = &RateFor(s, ModeFor(s.config.standard, s.phy.group_rate_mbps));
}

const RateEntry& RateFor(const State& s, const PhyMode& mode) {
  for (const RateEntry& entry : s.rates) {
    if (SameMode(entry.data.mode, mode)) return entry;
  }
  SITLNET_DEMAND(false && "rate not in the table");
  return s.rates.front();
}

void ChooseRates(State& s, int station) {
  StationState& st = s.stations[station];
  QueuedFrame& f = st.acs[st.exchange_ac].current;
  if (f.group) {
    f.rate = f.rts_rate = s.group_rate;
    return;
  }
  if (s.config.rate_control == MediumConfig::RateControl::kConstant) {
    f.rate = f.rts_rate = st.rate;
    return;
  }
  const double snr = LastSnr(st, f.destination);
  f.rate = &s.rates.front();
  f.rts_rate = nullptr;
  for (const RateEntry& entry : s.rates) {
    if (entry.ideal_snr_threshold < snr &&
        entry.data.mode.rate_mbps > f.rate->data.mode.rate_mbps) {
      f.rate = &entry;
    }
    if (entry.basic && entry.ideal_snr_threshold < snr &&
        (f.rts_rate == nullptr || entry.ideal_snr_threshold > f.rts_rate->ideal_snr_threshold)) {
      f.rts_rate = &entry;
    }
  }
  if (f.rts_rate == nullptr) f.rts_rate = &s.rates.front();  // ns-3: the default mode.
}

void ReportSnr(State& s, int station, const MacAddress& destination, double snr) {
  if (s.config.rate_control != MediumConfig::RateControl::kIdeal) return;
  StationState& st = s.stations[station];
  for (auto& [mac, last] : st.ideal_snr) {
    if (mac == destination) {
      last = snr;
      return;
    }
  }
  st.ideal_snr.emplace_back(destination, snr);
}

}  // namespace sitlnet::mac

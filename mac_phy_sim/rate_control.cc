// Rate selection: the table of rates of the standard with their control
// responses, the constant-rate manager, the choice of a station's manager,
// and the frame exchange's calls into it (rate_manager.h).
#include <cmath>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/gamma.h"
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
         a.spatial_streams == b.spatial_streams && a.channel_width_mhz == b.channel_width_mhz &&
         a.short_guard_interval == b.short_guard_interval;
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

// Every MCS a station may use with `channel_width_mhz` and the guard interval (stations may
// override the MCS; HT's index carries the streams, VHT's does not).
void AddMcsRates(State& s, int channel_width_mhz, bool short_guard_interval) {
  const bool vht = s.config.standard == Standard::k80211ac;
  for (int mcs = 0; mcs < (vht ? 10 : 16); ++mcs) {
    for (int streams = 1; streams <= 2; ++streams) {
      if (!vht && streams != mcs / 8 + 1) continue;
      try {
        const PhyMode mode =
            McsModeFor(s.config.standard, mcs, streams, channel_width_mhz, short_guard_interval);
        s.rates.push_back(MakeRate(s, mode));
      } catch (const Error&) {
        // VHT MCS 9 at 20 MHz: no such mode.
      }
    }
  }
}

// ns-3's ConstantRateWifiManager: the station's rate; RTS at that rate's control rate.
class ConstantRateManager final : public RateManager {
 public:
  explicit ConstantRateManager(const RateEntry* rate) : rate_(rate) {}
  TxRates Choose(const MacAddress& /*destination*/, TimeNs /*now_ns*/) override {
    return TxRates{rate_, rate_, &rate_->control};
  }

 private:
  const RateEntry* rate_;
};

}  // namespace

void BuildRates(State& s) {
  static constexpr double kAll[] = {1, 2, 5.5, 6, 9, 11, 12, 18, 24, 36, 48, 54};
  for (double rate : kAll) {
    if (!HasRate(s.config.standard, rate)) continue;  // n/ac: the legacy PHY's rates.
    s.rates.push_back(MakeRate(s, ModeFor(s.config.standard, rate)));
  }
  if (IsHtOrVht(s.config.standard)) {
    const PhyMode data = DataModeFor(s.config, StationRadio{});
    AddMcsRates(s, data.channel_width_mhz, data.short_guard_interval);
    if (s.config.rate_control == MediumConfig::RateControl::kMinstrel) {
      // Minstrel-HT's other groups: narrower widths, and the long GI beside the short one
      // (minstrel_ht_rate_manager.cc). Added after the config's own, so those keep their places.
      for (int width_mhz = 20; width_mhz <= data.channel_width_mhz; width_mhz *= 2) {
        for (const bool short_gi : {false, true}) {
          if (short_gi && !data.short_guard_interval) continue;
          const bool own = width_mhz == data.channel_width_mhz &&
                           short_gi == data.short_guard_interval;
          if (!own) AddMcsRates(s, width_mhz, short_gi);
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

std::unique_ptr<RateManager> MakeRateManager(const State& s, int station) {
  switch (s.config.rate_control) {
    case MediumConfig::RateControl::kConstant:
      return std::make_unique<ConstantRateManager>(s.stations[station].rate);
    case MediumConfig::RateControl::kIdeal:
      return MakeIdealRateManager(s);
    case MediumConfig::RateControl::kMinstrel: {
      // Its own stream ("minstrel"), apart from the MAC's and the channel's: turning it on
      // leaves every other draw as it was. 802.11n/ac: Minstrel-HT (ns-3's
      // MinstrelHtWifiManager, which runs legacy Minstrel for non-HT peers: the a/b/g one here).
      const uint64_t seed = SplitMix64(s.config.seed ^ 0x6d696e737472656cull ^
                                       SplitMix64(static_cast<uint64_t>(station) + 1));
      return IsHtOrVht(s.config.standard) ? MakeMinstrelHtRateManager(s, seed)
                                          : MakeMinstrelRateManager(s, seed);
    }
  }
  SITLNET_DEMAND(false && "unknown rate control");
  return nullptr;
}

void ChooseRates(State& s, int station) {
  StationState& st = s.stations[station];
  QueuedFrame& f = st.acs[st.exchange_ac].current;
  if (f.group) {
    f.rate = f.rts_rate = s.group_rate;
    f.rts_mode = &s.group_rate->control;
    return;
  }
  const TxRates rates = st.rate_manager->Choose(f.destination, s.now_ns);
  f.rate = rates.data;
  f.rts_rate = rates.rts;
  f.rts_mode = rates.rts_mode;
}

}  // namespace sitlnet::mac

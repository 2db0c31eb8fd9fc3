// The public API of the medium and its event loop.
#include <cmath>
#include <limits>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

double DbmToMw(double dbm) { return std::pow(10.0, dbm / 10); }

bool IsStale(const State& s, const Event& e) {
  switch (e.type) {
    case EventType::kTimeout:
      return e.aux != s.stations[e.station].timeout_generation;
    default:
      return false;
  }
}

void Dispatch(State& s, const Event& e) {
  switch (e.type) {
    case EventType::kEnqueue: {
      PendingFrame& pending = s.pending_frames[e.aux];
      Bytes bytes = std::move(pending.ethernet);
      s.free_pending_frames.push_back(static_cast<int>(e.aux));
      OnEnqueue(s, e.station, std::move(bytes));
      return;
    }
    case EventType::kMove:
      s.channel.SetPosition(e.station, s.pending_moves[e.aux].position_m);
      if (s.speed_doppler) {
        s.speed_doppler->Move(e.station, s.pending_moves[e.aux].position_m, s.now_ns);
      }
      s.free_pending_moves.push_back(static_cast<int>(e.aux));
      return;
    case EventType::kTxEnd:
      OnTxEnd(s, static_cast<int>(e.aux));
      return;
    case EventType::kTimeout:
      OnTimeout(s, e.station, e.aux);
      return;
    case EventType::kRespond:
      OnRespond(s, e.station);
      return;
    case EventType::kNavEnd:
      s.stations[e.station].nav_event_ns = -1;
      UpdateCca(s, e.station);
      return;
    case EventType::kSignalStart:
      OnSignalStart(s, static_cast<int>(e.aux >> 32), static_cast<int>(e.aux & 0xffffffffu));
      return;
    case EventType::kSignalEnd:
      OnSignalEnd(s, static_cast<int>(e.aux >> 32), static_cast<int>(e.aux & 0xffffffffu));
      return;
    case EventType::kContinueTxop:
      OnContinueTxop(s, e.station, static_cast<int>(e.aux));
      return;
    case EventType::kBlockAckReqDue:
      OnBlockAckReqDue(s, e.station, static_cast<int>(e.aux));
      return;
  }
}

}  // namespace

Medium::State::State(const MediumConfig& config_in, const PhyInfo& phy_in)
    : config(config_in),
      phy(phy_in),
      channel(MakePathLossModel(config_in, phy_in), config_in.shadowing,
              config_in.shadowing_db_per_wall, config_in.shadowing_db_per_m) {
  // Below the sensitivity a signal is not even tracked as interference.
  // With fading, a link up to fading_margin_db weaker on average can still be
  // received (transmission.cc), so its loss must stay exact.
  max_tx_power_dbm = config.tx_power_dbm;
  if (config.nakagami_fading) fading_margin_db = kFadingMarginDb;
  if (config.jakes_fading) {
    fading_margin_db = JakesProcess::MaxPowerGainDb(config.jakes_oscillators);
    // Its own stream ("jakes"), apart from the MAC's and Nakagami's.
    jakes.emplace(JakesParameters{config.jakes_doppler_hz, config.jakes_oscillators},
                  SplitMix64(config.seed ^ 0x6a616b6573000000ull));
    if (config.jakes_doppler_from_speed) {
      speed_doppler.emplace(kSpeedOfLightMps / (phy.frequency_mhz * 1e6));
    }
  }
  channel.set_dead_link_loss_db(config.tx_power_dbm - config.rx_sensitivity_dbm +
                                fading_margin_db);
  channel.set_clock(&now_ns);  // For 3GPP's update period (State is neither copied nor moved).
  channel.set_lognormal_shadowing(config.lognormal_shadowing_sigma_db,
                                  SplitMix64(config.seed ^ 0x6c6f676e6f726d61ull));
  noise_mw = DbmToMw(phy.noise_floor_dbm);
  cca_mw = DbmToMw(config.cca_energy_detect_dbm);
  preamble_snr_linear = std::pow(10.0, config.preamble_detect_snr_db / 10);
  if (config.nakagami_fading) {
    const double m[3] = {config.nakagami_m0, config.nakagami_m1, config.nakagami_m2};
    for (int k = 0; k < 3; ++k) fading[k] = GammaSampler(m[k]);
  }
  BuildRates(*this);
}

Medium::Medium(const MediumConfig& config)
    : state_(std::make_unique<State>(config, DerivePhyInfo(config))) {}
Medium::~Medium() = default;
Medium::Medium(Medium&&) noexcept = default;
Medium& Medium::operator=(Medium&&) noexcept = default;

const MediumConfig& Medium::config() const { return state_->config; }
const PhyInfo& Medium::phy() const { return state_->phy; }
int Medium::station_count() const { return static_cast<int>(state_->stations.size()); }
TimeNs Medium::now_ns() const { return state_->now_ns; }

StationId Medium::AddStation(const MacAddress& mac, const Vec3d& position_m) {
  return AddStation(mac, position_m, StationRadio{});
}

StationId Medium::AddStation(const MacAddress& mac, const Vec3d& position_m,
                             const StationRadio& radio) {
  State& s = *state_;
  const double tx_power_dbm = radio.tx_power_dbm.value_or(s.config.tx_power_dbm);
  // Its range is the scenario's (Radio.tx_power_dbm's options), checked at load.
  SITLNET_DEMAND(std::isfinite(tx_power_dbm));
  PhyMode data_mode;
  try {
    data_mode = DataModeFor(s.config, radio);
  } catch (const Error& e) {
    throw Error(std::string("station radio: ") + e.what());
  }
  if (tx_power_dbm > s.max_tx_power_dbm) {
    // Links are "dead" below the sensitivity for the strongest transmitter.
    s.max_tx_power_dbm = tx_power_dbm;
    s.channel.set_dead_link_loss_db(tx_power_dbm - s.config.rx_sensitivity_dbm +
                                    s.fading_margin_db);
    s.channel.InvalidateAll();
  }
  const int id = static_cast<int>(s.stations.size());
  StationState& st = s.stations.emplace_back();
  st.mac = mac;
  st.tx_power_dbm = tx_power_dbm;
  st.tx_power_mw = DbmToMw(tx_power_dbm);
  st.rate = &RateFor(s, data_mode);
  st.rng.seed(SplitMix64(s.config.seed ^ SplitMix64(static_cast<uint64_t>(id) + 1)));
  // A stream of its own, so turning fading on leaves the other draws as they were.
  st.fading_rng.seed(SplitMix64(~s.config.seed ^ SplitMix64(static_cast<uint64_t>(id) + 1)));
  st.rate_manager = MakeRateManager(s, id);
  // Path loss ref + 10 n log10(d) (the reference loss up to 1 m) under the
  // margin's loss; a hair wider, as links drawn in vain are still dead for
  // the exact loss (transmission.cc). Log-normal shadowing can lower any
  // link's loss, and other path-loss models are not log-distance: no limit then.
  const double margin_loss_db =
      tx_power_dbm - s.config.rx_sensitivity_dbm + s.fading_margin_db - s.phy.reference_loss_db;
  st.fading_reach_m2 =
      s.config.lognormal_shadowing_sigma_db > 0 || !s.channel.path_loss_model().IsLogDistance()
          ? std::numeric_limits<double>::infinity()
          : (margin_loss_db <= 0
                 ? 0.0
                 : std::pow(10.0, margin_loss_db / (5 * s.config.path_loss_exponent)) * (1 + 1e-9));
  for (int ac = 0; ac < kAccessCategoryCount; ++ac) st.acs[ac].cw = s.phy.edca[ac].cw_min;
  st.idle_since_ns = s.now_ns;
  s.channel.AddStation(position_m);
  if (s.speed_doppler) s.speed_doppler->AddStation(position_m, s.now_ns);
  return id;
}

void Medium::SetStationPosition(StationId station, const Vec3d& position_m, TimeNs at_ns) {
  State& s = *state_;
  SITLNET_DEMAND(station >= 0 && station < station_count());
  int slot;
  if (!s.free_pending_moves.empty()) {
    slot = s.free_pending_moves.back();
    s.free_pending_moves.pop_back();
  } else {
    slot = static_cast<int>(s.pending_moves.size());
    s.pending_moves.emplace_back();
  }
  s.pending_moves[slot] = PendingMove{station, position_m};
  s.scheduler.Push(std::max(at_ns, s.now_ns), EventType::kMove, station,
                   static_cast<uint64_t>(slot));
}

void Medium::AddObstacle(const Box& box) { state_->channel.AddObstacle(box); }

bool Medium::SubmitFrame(StationId source, std::span<const uint8_t> ethernet_frame, TimeNs at_ns) {
  State& s = *state_;
  SITLNET_DEMAND(source >= 0 && source < station_count());
  StationState& st = s.stations[source];
  if (ethernet_frame.size() < static_cast<size_t>(kEthernetHeaderBytes) ||
      ethernet_frame.size() - kEthernetHeaderBytes + kLlcSnapBytes > kMaxMsduBytes) {
    ++st.counters.malformed;
    return false;
  }
  ++st.counters.frames_submitted;
  int slot;
  if (!s.free_pending_frames.empty()) {
    slot = s.free_pending_frames.back();
    s.free_pending_frames.pop_back();
  } else {
    slot = static_cast<int>(s.pending_frames.size());
    s.pending_frames.emplace_back();
  }
  s.pending_frames[slot] = PendingFrame{source, std::make_shared<const std::vector<uint8_t>>(
                                                    ethernet_frame.begin(), ethernet_frame.end())};
  s.scheduler.Push(std::max(at_ns, s.now_ns), EventType::kEnqueue, source,
                   static_cast<uint64_t>(slot));
  return true;
}

void Medium::AdvanceTo(TimeNs until_ns, std::vector<Delivery>* deliveries) {
  State& s = *state_;
  s.deliveries = deliveries;
  while (true) {
    while (!s.scheduler.empty() && IsStale(s, s.scheduler.top())) s.scheduler.Pop();
    TimeNs access_ns;
    int access_station;
    s.EarliestAccess(&access_ns, &access_station);
    const bool have_event = !s.scheduler.empty() && s.scheduler.top().time_ns <= until_ns;
    const bool have_access = access_station >= 0 && access_ns <= until_ns;
    if (!have_event && !have_access) break;
    // Queued events first at equal times, then backoff expiries by station id.
    if (have_event && (!have_access || s.scheduler.top().time_ns <= access_ns)) {
      const Event event = s.scheduler.Pop();
      s.now_ns = event.time_ns;
      Dispatch(s, event);
    } else {
      s.now_ns = access_ns;
      OnAccess(s, access_station);
    }
  }
  if (until_ns > s.now_ns) s.now_ns = until_ns;
  s.deliveries = nullptr;
}

std::optional<TimeNs> Medium::NextEventNs() {
  State& s = *state_;
  while (!s.scheduler.empty() && IsStale(s, s.scheduler.top())) s.scheduler.Pop();
  TimeNs access_ns;
  int access_station;
  s.EarliestAccess(&access_ns, &access_station);
  if (s.scheduler.empty()) {
    if (access_station < 0) return std::nullopt;
    return access_ns;
  }
  const TimeNs event_ns = s.scheduler.top().time_ns;
  return access_station >= 0 ? std::min(event_ns, access_ns) : event_ns;
}

void Medium::EnableTrace(bool enabled) { state_->trace_enabled = enabled; }

void Medium::EnableCauses(bool enabled) {
  state_->record_causes = enabled;
  for (StationState& st : state_->stations) st.active.clear();
}

void Medium::DrainTrace(std::vector<TraceEvent>* out) {
  for (TraceEvent& event : state_->trace) out->push_back(std::move(event));
  state_->trace.clear();
}

const StationCounters& Medium::counters(StationId station) const {
  SITLNET_DEMAND(station >= 0 && station < station_count());
  return state_->stations[station].counters;
}

size_t Medium::queued_frames(StationId station) const {
  SITLNET_DEMAND(station >= 0 && station < station_count());
  size_t queued = 0;
  for (const AccessFunction& f : state_->stations[station].acs) queued += f.queue.size();
  return queued;
}

double Medium::LossDb(StationId a, StationId b) {
  SITLNET_DEMAND(a >= 0 && a < station_count() && b >= 0 && b < station_count());
  return a == b ? 0.0 : state_->channel.LossDb(a, b);
}

}  // namespace sitlnet::mac

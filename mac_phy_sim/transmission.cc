// Putting a PPDU on the air (power at every station from the channel cache,
// optional Nakagami fading and propagation delay) and taking it off (end of
// reception everywhere, MAC reactions, trace).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

double SquaredDistanceM2(const RadioChannel& channel, int a, int b);

// record_causes: splits the loss a -> b into path loss and obstacle shadowing,
// with the channel's own terms (RadioChannel::ComputeLoss adds these three).
template <typename T>
void SplitLoss(State& s, int a, int b, double loss_db, T* path_db, T* obstacle_db) {
  const double path = s.channel.PathLossDb(a, b);
  *path_db = static_cast<T>(path);
  *obstacle_db = static_cast<T>(loss_db - path - s.channel.LognormalDb(a, b));
}

void TraceTransmission(State& s, const Transmission& tx) {
  TxRecord record;
  record.start_ns = tx.start_ns;
  record.end_ns = tx.end_ns;
  record.source = tx.source;
  record.kind = tx.kind;
  record.retry = tx.retry;
  record.sequence_number = tx.sequence_number;
  record.duration_us = tx.duration_us;
  const PhyMode& mode = tx.mode->mode;
  record.rate_mbps = mode.rate_mbps;
  if (mode.format != PhyFormat::kLegacy) {
    record.mcs = mode.mcs;
    record.vht = mode.format == PhyFormat::kVht;
    record.spatial_streams = mode.spatial_streams;
    record.channel_width_mhz = mode.channel_width_mhz;
    record.short_guard_interval = mode.short_guard_interval;
  }
  record.qos = tx.kind == FrameKind::kData && s.phy.qos;
  record.tid = tx.tid;
  record.receiver = tx.ra;
  record.transmitter = tx.ta;
  if (tx.kind == FrameKind::kData) record.ethernet_frame = tx.ethernet;
  const int n = static_cast<int>(s.stations.size());
  record.receptions.reserve(n - 1);
  size_t next_entry = 0;
  for (int r = 0; r < n; ++r) {
    if (r == tx.source) continue;
    if (next_entry < tx.rx.size() && tx.rx[next_entry].station == r) {
      const RxEntry& e = tx.rx[next_entry++];
      record.receptions.push_back({r, e.outcome, e.power_dbm, 10 * std::log10(e.sinr)});
      if (s.record_causes) {
        RxRecord& out = record.receptions.back();
        out.cause = e.cause;
        out.interferer = e.interferer;
        out.path_loss_db = e.path_loss_db;
        out.obstacle_loss_db = e.obstacle_loss_db;
      }
    } else {
      const double loss_db = s.channel.LossDb(tx.source, r);
      const double dbm = s.stations[tx.source].tx_power_dbm - loss_db;
      record.receptions.push_back(
          {r, RxOutcome::kBelowSensitivity, dbm, dbm - s.phy.noise_floor_dbm});
      if (s.record_causes) {
        RxRecord& out = record.receptions.back();
        out.cause = RxCause::kBelowThreshold;
        // Only where it could matter (a sensitivity above the noise floor); positions may
        // have changed since the start: the split is that of now.
        if (dbm >= s.phy.noise_floor_dbm) {
          SplitLoss(s, tx.source, r, loss_db, &out.path_loss_db, &out.obstacle_loss_db);
        }
      }
    }
    if (s.record_causes && tx.kind == FrameKind::kData) {
      RxRecord& out = record.receptions.back();
      // A wall that took loss crossed the path; otherwise ask the geometry: the loss split is
      // cut short on dead links, and the 3GPP models put their NLOS loss in the path loss.
      out.obstructed = out.obstacle_loss_db > kObstructedMinLossDb ||
                       (s.channel.obstacle_count() > 0 &&
                        s.channel.SegmentBlocked(s.channel.position(tx.source),
                                                 s.channel.position(r)));
    }
  }
  record.addba_response = tx.addba_response;
  record.ba_starting_sequence = tx.ba_ssn;
  record.ba_bitmap = tx.ba_bitmap;
  if (tx.subframes.empty()) {
    TraceEvent event;
    event.tx = std::move(record);
    s.trace.push_back(std::move(event));
    return;
  }
  // An A-MPDU: one record per MPDU (what a capture shows), each with the A-MPDU's reference;
  // the addressed receiver's outcome is the MPDU's own.
  const int count = static_cast<int>(tx.subframes.size());
  record.ampdu_reference = tx.ampdu_reference;
  for (int i = 0; i < count; ++i) {
    TraceEvent event;
    event.tx = record;
    TxRecord& r = *event.tx;
    const AmpduSubframe& m = tx.subframes[i];
    r.sequence_number = m.sequence_number;
    r.retry = m.retry;
    r.ethernet_frame = m.ethernet;
    r.ampdu_last = i + 1 == count;
    for (RxRecord& rx : r.receptions) {
      if (s.stations[rx.station].mac == tx.ra && !tx.subframe_outcome.empty() &&
          rx.outcome == RxOutcome::kReceived) {
        rx.outcome = tx.subframe_outcome[i];
      }
    }
    s.trace.push_back(std::move(event));
  }
}

void CountReceiverOutcome(StationState& st, const Transmission& tx, const RxEntry& e) {
  // Receive-side loss counters cover DATA frames meant for the station.
  if (tx.kind != FrameKind::kData || !(tx.group || tx.ra == st.mac)) return;
  switch (e.outcome) {
    case RxOutcome::kCollided:
      ++st.counters.rx_collided;
      break;
    case RxOutcome::kError:
      ++st.counters.rx_error;
      break;
    case RxOutcome::kBelowSensitivity:
      ++st.counters.rx_below_sensitivity;
      break;
    default:
      break;
  }
}

double SquaredDistanceM2(const RadioChannel& channel, int a, int b) {
  const Vec3d& pa = channel.position(a);
  const Vec3d& pb = channel.position(b);
  const double dx = pb.x - pa.x, dy = pb.y - pa.y, dz = pb.z - pa.z;
  return dx * dx + dy * dy + dz * dz;
}

// ns-3 NakagamiPropagationLossModel: m by distance (d < d1: m0; d < d2: m1;
// else m2). Returns which of the three.
int NakagamiIndex(const MediumConfig& c, double squared_distance_m2) {
  if (squared_distance_m2 < c.nakagami_d1_m * c.nakagami_d1_m) return 0;
  return squared_distance_m2 < c.nakagami_d2_m * c.nakagami_d2_m ? 1 : 2;
}

// Nakagami fading (ns-3 NakagamiPropagationLossModel): the received power of
// one frame at `r` is the mean power times a Gamma(m, 1/m) gain, drawn per
// frame and receiver, in receiver order, from the transmitter's fading stream.
// Returns false if the frame stays under the RX sensitivity at `r`, else its
// power in dBm and mW.
//
// Most links of a fleet among obstacles are far under the sensitivity, so
// deciding that cheaply is what counts. The gain does not depend on the loss:
// it is drawn first, and the loss is then resolved only as far as the decision
// needs (RadioChannel::LossDbUntil stops the obstacle walk once the link is
// certainly under the sensitivity for this gain: on average a few dB earlier
// than without fading). For m < 1 the Gamma(m + 1) draw of the boost (gamma.h)
// bounds the gain from above and decides the weak links alone; U^(1/m) is
// drawn only for the rest; the threshold uses a cheap upper bound of log10.
// Links more than kFadingMarginDb under the sensitivity on path loss alone
// draw nothing; any link that far under is dead (gains that large have
// probability <= 2.5e-10).
bool FadedPower(State& s, int source, int r, double* dbm, double* mw, double* loss_out_db) {
  StationState& src = s.stations[source];
  const double d2 = SquaredDistanceM2(s.channel, source, r);
  if (!(d2 < src.fading_reach_m2)) return false;
  const MediumConfig& config = s.config;
  const GammaSampler& sampler = s.fading[NakagamiIndex(config, d2)];
  // Gamma(m, 1/m) = Gamma(m, 1) / m; boosted: this is the bound Gamma(m + 1, 1) / m.
  const double base = sampler.Base(src.fading_rng) * sampler.inverse_shape();
  // The mean power reaches the sensitivity at this loss; with the gain, at this plus its dB.
  const double sensitivity_loss_db = src.tx_power_dbm - config.rx_sensitivity_dbm;
  const double stop_db =
      sensitivity_loss_db + std::min(10 * Log10UpperBound(base), kFadingMarginDb);
  const double loss_db = s.channel.LossDbUntil(source, r, stop_db);
  if (!(loss_db < stop_db)) return false;  // A lower bound: under the sensitivity anyway.
  double gain_db = 10 * std::log10(base);
  if (sampler.boosted()) {
    gain_db += (10 / std::numbers::ln10) * sampler.LogBoost(src.fading_rng);
  }
  *dbm = src.tx_power_dbm - loss_db + gain_db;
  if (*dbm < config.rx_sensitivity_dbm) return false;
  *loss_out_db = loss_db;
  *mw = std::pow(10.0, *dbm / 10);
  return true;
}

// Jakes fading (ns-3 JakesPropagationLossModel): the received power of a frame at `r` is the
// mean power times the pair's process's power gain at the frame's start. Returns false if the
// frame stays under the RX sensitivity at `r`, else its power in dBm and mW. No gain exceeds
// fading_margin_db (10 log10(2 M), exact), so links weaker on average by more are resolved
// only that far and create no process.
bool JakesFadedPower(State& s, int source, int r, double* dbm, double* mw, double* loss_out_db) {
  const StationState& src = s.stations[source];
  if (!(SquaredDistanceM2(s.channel, source, r) < src.fading_reach_m2)) return false;
  const double stop_db = src.tx_power_dbm - s.config.rx_sensitivity_dbm + s.fading_margin_db;
  const double loss_db = s.channel.LossDbUntil(source, r, stop_db);
  if (!(loss_db < stop_db)) return false;
  const double gain_db =
      s.speed_doppler
          ? s.jakes->PowerGainDbAtPhase(source, r, s.speed_doppler->PhaseRad(source, r, s.now_ns))
          : s.jakes->PowerGainDb(source, r, s.now_ns);
  *dbm = src.tx_power_dbm - loss_db + gain_db;
  if (!(*dbm >= s.config.rx_sensitivity_dbm)) return false;
  *loss_out_db = loss_db;
  *mw = std::pow(10.0, *dbm / 10);
  return true;
}

// The receiver side of the end of signal `i` of `tx`: reception outcome, NAV,
// CCA, MAC reactions.
void EndAtReceiver(State& s, Transmission& tx, int i) {
  const int r = tx.rx[i].station;
  StationState& st = s.stations[r];
  const bool was_locked = st.rx.tx == tx.id;
  const bool decoded = SignalEnds(s, r, tx, i);
  // Virtual carrier sense from any decoded frame addressed to someone else.
  if (decoded && !(tx.ra == st.mac) && tx.duration_us > 0) {
    SetNav(s, r, s.now_ns + tx.duration_us * kNsPerUs);
  }
  // A CF-End resets the NAV (9.3.1.9; ns-3's NavResetTimeout).
  if (decoded && tx.kind == FrameKind::kCfEnd) st.nav_until_ns = std::min(st.nav_until_ns, s.now_ns);
  UpdateCca(s, r);
  CountReceiverOutcome(st, tx, tx.rx[i]);
  if (decoded) OnFrameReceived(s, r, tx, tx.rx[i]);
  if (was_locked) OnLockedRxEnd(s, r);
}

// Everyone is done with `tx`: trace it and return it to the pool.
void Release(State& s, Transmission& tx) {
  if (s.trace_enabled) TraceTransmission(s, tx);
  tx.ethernet.reset();
  tx.subframes.clear();
  s.free_transmissions.push_back(tx.id);
}

uint64_t SignalAux(int tx_id, int entry) {
  return (static_cast<uint64_t>(tx_id) << 32) | static_cast<uint32_t>(entry);
}

}  // namespace

Transmission& StartTransmission(State& s, int source, FrameKind kind, const ModeEntry& mode,
                                int psdu_bytes, const MacAddress& ra, uint16_t duration_us,
                                std::vector<AmpduSubframe>* subframes) {
  int id;
  if (!s.free_transmissions.empty()) {
    id = s.free_transmissions.back();
    s.free_transmissions.pop_back();
  } else {
    id = static_cast<int>(s.transmissions.size());
    s.transmissions.emplace_back();
  }
  Transmission& tx = s.transmissions[id];
  tx.id = id;
  tx.source = source;
  tx.kind = kind;
  tx.mode = &mode;
  tx.start_ns = s.now_ns;
  tx.end_ns = s.now_ns + PpduDurationNs(mode.mode, mode.header, psdu_bytes);
  tx.ra = ra;
  tx.ta = s.stations[source].mac;
  tx.duration_us = duration_us;
  tx.group = ra.IsGroup();
  tx.retry = false;
  tx.sequence_number = 0;
  tx.tid = 0;
  tx.ethernet.reset();
  tx.subframes.clear();
  if (subframes != nullptr) tx.subframes.swap(*subframes);
  tx.subframe_outcome.clear();
  tx.addba_response = false;
  tx.ba_ssn = 0;
  tx.ba_bitmap = 0;
  tx.reported_snr = 0;
  tx.rx.clear();
  tx.signals_pending = 0;
  tx.on_air = true;

  StationState& src = s.stations[source];
  AbortReception(s, source);
  src.transmitting_tx = id;
  // EIFS protects a frame this station could not decode; after its own
  // transmission DIFS applies again (ns-3 measures EIFS from the failed
  // reception, so the later transmission end dominates).
  src.use_eifs = false;
  UpdateCca(s, source);
  const MediumConfig& config = s.config;
  const int n = static_cast<int>(s.stations.size());
  auto add_receiver = [&](int r, double dbm, double mw, double loss_db) {
    TimeNs delay_ns = 0;
    if (config.propagation_delay) {
      // Nothing farther than light travels in a second hears the frame: no radio reaches that
      // far (only a radio allowed 230 dB of loss comes near), and the delay would carry the
      // signal's events past int64's end.
      const double delay_s = std::sqrt(SquaredDistanceM2(s.channel, source, r)) / kSpeedOfLightMps;
      if (!(delay_s < 1.0)) return;
      delay_ns = std::llround(delay_s * 1e9);
    }
    tx.rx.push_back({r, mw, dbm, RxOutcome::kBelowSensitivity, 0, delay_ns});
    if (s.record_causes) {
      RxEntry& e = tx.rx.back();
      SplitLoss(s, source, r, loss_db, &e.path_loss_db, &e.obstacle_loss_db);
    }
  };
  if (config.nakagami_fading || config.jakes_fading) {
    const auto faded_power = config.jakes_fading ? JakesFadedPower : FadedPower;
    for (int r = 0; r < n; ++r) {
      double dbm, mw, loss_db;
      if (r != source && faded_power(s, source, r, &dbm, &mw, &loss_db)) {
        add_receiver(r, dbm, mw, loss_db);
      }
    }
  } else {
    for (int r = 0; r < n; ++r) {
      if (r == source) continue;
      const double loss_db = s.channel.LossDb(source, r);
      const double dbm = src.tx_power_dbm - loss_db;
      // Written so that a station at a position that is not a number hears nothing.
      if (!(dbm >= config.rx_sensitivity_dbm)) continue;
      add_receiver(r, dbm, src.tx_power_mw * s.channel.GainLinear(source, r), loss_db);
    }
  }
  for (int i = 0; i < static_cast<int>(tx.rx.size()); ++i) {
    const RxEntry& entry = tx.rx[i];
    if (entry.delay_ns == 0) {
      SignalArrives(s, entry.station, tx, i);
      UpdateCca(s, entry.station);
      continue;
    }
    ++tx.signals_pending;
    s.scheduler.Push(tx.start_ns + entry.delay_ns, EventType::kSignalStart, entry.station,
                     SignalAux(id, i));
    s.scheduler.Push(tx.end_ns + entry.delay_ns, EventType::kSignalEnd, entry.station,
                     SignalAux(id, i));
  }
  s.scheduler.Push(tx.end_ns, EventType::kTxEnd, source, static_cast<uint64_t>(id));
  return tx;
}

void OnTxEnd(State& s, int tx_id) {
  Transmission& tx = s.transmissions[tx_id];
  tx.on_air = false;
  s.stations[tx.source].transmitting_tx = -1;
  for (int i = 0; i < static_cast<int>(tx.rx.size()); ++i) {
    if (tx.rx[i].delay_ns == 0) EndAtReceiver(s, tx, i);
  }
  UpdateCca(s, tx.source);
  OnOwnTxEnd(s, tx);
  if (tx.signals_pending == 0) Release(s, tx);
}

void OnSignalStart(State& s, int tx_id, int entry) {
  Transmission& tx = s.transmissions[tx_id];
  const int r = tx.rx[entry].station;
  SignalArrives(s, r, tx, entry);
  UpdateCca(s, r);
}

void OnSignalEnd(State& s, int tx_id, int entry) {
  Transmission& tx = s.transmissions[tx_id];
  EndAtReceiver(s, tx, entry);
  if (--tx.signals_pending == 0 && !tx.on_air) Release(s, tx);
}

}  // namespace sitlnet::mac

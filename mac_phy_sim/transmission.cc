// Putting a PPDU on the air (power at every station from the channel cache)
// and taking it off (end of reception everywhere, MAC reactions, trace).
#include <cmath>

#include "mac_phy_sim/medium_state.h"
#include "mac_phy_sim/mpdu.h"

namespace sitlnet::mac {
namespace {

void TraceTransmission(State& s, const Transmission& tx) {
  TxRecord record;
  record.start_ns = tx.start_ns;
  record.end_ns = tx.end_ns;
  record.source = tx.source;
  record.kind = tx.kind;
  record.retry = tx.retry;
  record.sequence_number = tx.sequence_number;
  record.duration_us = tx.duration_us;
  record.rate_mbps = tx.mode->mode.rate_mbps;
  record.receiver = tx.ra;
  record.transmitter = tx.ta;
  if (tx.kind == FrameKind::kData) {
    BuildDataMpdu(tx.ra, tx.ta, tx.duration_us, tx.sequence_number, tx.retry, *tx.ethernet,
                  &record.mpdu);
  } else {
    BuildControlMpdu(tx.kind, tx.ra, tx.ta, tx.duration_us, &record.mpdu);
  }
  const int n = static_cast<int>(s.stations.size());
  record.receptions.reserve(n - 1);
  size_t next_entry = 0;
  for (int r = 0; r < n; ++r) {
    if (r == tx.source) continue;
    if (next_entry < tx.rx.size() && tx.rx[next_entry].station == r) {
      const RxEntry& e = tx.rx[next_entry++];
      record.receptions.push_back({r, e.outcome, e.power_dbm, 10 * std::log10(e.sinr)});
    } else {
      const double dbm = s.config.tx_power_dbm - s.channel.LossDb(tx.source, r);
      record.receptions.push_back(
          {r, RxOutcome::kBelowSensitivity, dbm, dbm - s.phy.noise_floor_dbm});
    }
  }
  TraceEvent event;
  event.tx = std::move(record);
  s.trace.push_back(std::move(event));
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

}  // namespace

Transmission& StartTransmission(State& s, int source, FrameKind kind, const ModeEntry& mode,
                                int psdu_bytes, const MacAddress& ra, uint16_t duration_us) {
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
  tx.ethernet.reset();
  tx.rx.clear();

  StationState& src = s.stations[source];
  AbortReception(s, source);
  src.transmitting_tx = id;
  // EIFS protects a frame this station could not decode; after its own
  // transmission DIFS applies again (ns-3 measures EIFS from the failed
  // reception, so the later transmission end dominates).
  src.use_eifs = false;
  UpdateCca(s, source);
  const int n = static_cast<int>(s.stations.size());
  for (int r = 0; r < n; ++r) {
    if (r == source) continue;
    const double dbm = s.config.tx_power_dbm - s.channel.LossDb(source, r);
    if (dbm < s.config.rx_sensitivity_dbm) continue;
    tx.rx.push_back(
        {r, s.tx_power_mw * s.channel.GainLinear(source, r), dbm, RxOutcome::kBelowSensitivity, 0});
  }
  for (int i = 0; i < static_cast<int>(tx.rx.size()); ++i) {
    SignalArrives(s, tx.rx[i].station, tx, i);
    UpdateCca(s, tx.rx[i].station);
  }
  s.scheduler.Push(tx.end_ns, EventType::kTxEnd, source, static_cast<uint64_t>(id));
  return tx;
}

void OnTxEnd(State& s, int tx_id) {
  Transmission& tx = s.transmissions[tx_id];
  s.stations[tx.source].transmitting_tx = -1;
  for (int i = 0; i < static_cast<int>(tx.rx.size()); ++i) {
    const int r = tx.rx[i].station;
    StationState& st = s.stations[r];
    const bool was_locked = st.rx.tx == tx_id;
    const bool decoded = SignalEnds(s, r, tx, i);
    // Virtual carrier sense from any decoded frame addressed to someone else.
    if (decoded && !(tx.ra == st.mac) && tx.duration_us > 0) {
      SetNav(s, r, s.now_ns + tx.duration_us * kNsPerUs);
    }
    UpdateCca(s, r);
    CountReceiverOutcome(st, tx, tx.rx[i]);
    if (decoded) OnFrameReceived(s, r, tx, tx.rx[i]);
    if (was_locked) OnLockedRxEnd(s, r);
  }
  UpdateCca(s, tx.source);
  OnOwnTxEnd(s, tx);
  if (s.trace_enabled) TraceTransmission(s, tx);
  tx.ethernet.reset();
  s.free_transmissions.push_back(tx_id);
}

}  // namespace sitlnet::mac

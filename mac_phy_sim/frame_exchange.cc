// Frame exchange (IEEE 802.11-2016 10.3.2.5-10.3.2.11, 10.3.4.4): queue,
// DATA/ACK and RTS/CTS/DATA/ACK sequences, ACK/CTS timeouts (ns-3: SIFS +
// slot + PHY preamble/header), retries with short/long retry counters and
// binary exponential backoff, duplicate filtering by (TA, sequence number).
#include <algorithm>
#include <cmath>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

uint16_t Micros(TimeNs ns) { return static_cast<uint16_t>((ns + kNsPerUs - 1) / kNsPerUs); }

int DataMpduBytes(const State& s, const QueuedFrame& frame) {
  return MpduBytesForEthernet(static_cast<int>(frame.ethernet->size()), s.phy.qos);
}

// The PSDU of the current attempt (its rate chosen): a VHT one is an S-MPDU.
int DataPsduBytes(const State& s, const QueuedFrame& frame) {
  const bool vht = frame.rate->data.mode.format == PhyFormat::kVht;
  return DataMpduBytes(s, frame) + (vht ? kMpduDelimiterBytes : 0);
}

TimeNs DataDurationNs(const State& s, const QueuedFrame& frame) {
  return PpduDurationNs(frame.rate->data.mode, frame.rate->data.header, DataPsduBytes(s, frame));
}

void TraceDrop(State& s, int station, DropReason reason, const MacAddress& destination,
               uint16_t sequence_number, size_t bytes) {
  if (!s.trace_enabled) return;
  TraceEvent event;
  event.drop = DropRecord{s.now_ns, station, reason, destination, sequence_number, bytes};
  s.trace.push_back(std::move(event));
}

// Takes the next queued frame into service, if any.
void NextFrame(State& s, int station) {
  StationState& st = s.stations[station];
  st.has_current = false;
  if (st.queue.empty()) return;
  st.current = std::move(st.queue.front());
  st.queue.pop_front();
  st.has_current = true;
  st.current.sequence_number = st.next_sequence_number;
  st.next_sequence_number = static_cast<uint16_t>((st.next_sequence_number + 1) & 0x0fff);
}

// The frame in service is done (acknowledged, sent to a group, or dropped):
// reset CW and run a post-backoff (10.3.4.3), carrying the next frame if any.
void FinishCurrent(State& s, int station) {
  StationState& st = s.stations[station];
  st.exchange = Exchange::kIdle;
  st.cw = s.phy.cw_min;
  NextFrame(s, station);
  StartBackoff(s, station);
}

void ExchangeFailed(State& s, int station) {
  StationState& st = s.stations[station];
  const bool was_cts = st.exchange == Exchange::kWaitCts;
  st.exchange = Exchange::kIdle;
  st.timeout_waits_for_rx = false;
  ++st.counters.tx_failures;
  QueuedFrame& f = st.current;
  // Station retry counts (10.3.4.4): SRC for RTS and short DATA, LRC for DATA
  // after a CTS; at the limit the frame in service is discarded.
  const bool data_after_cts = !was_cts && f.use_rts;
  int& count = data_after_cts ? st.long_retry_count : st.short_retry_count;
  ++count;
  const int limit = data_after_cts ? s.config.long_retry_limit : s.config.short_retry_limit;
  if (count >= limit) {
    count = 0;
    ++st.counters.lost_retry_limit;
    TraceDrop(s, station, DropReason::kRetryLimit, f.destination, f.sequence_number,
              f.ethernet->size());
    FinishCurrent(s, station);
    return;
  }
  st.cw = std::min(2 * st.cw + 1, s.phy.cw_max);
  StartBackoff(s, station);
}

void ScheduleResponse(State& s, int station, FrameKind kind, const MacAddress& ra,
                      uint16_t duration_us, const RateEntry* answered = nullptr, double snr = 0) {
  StationState& st = s.stations[station];
  st.response_rate = answered;
  st.response_snr = snr;
  st.response_pending = true;
  st.response_kind = kind;
  st.response_ra = ra;
  st.response_duration_us = duration_us;
  s.scheduler.Push(s.now_ns + s.phy.sifs_ns, EventType::kRespond, station, 0);
}

void SendData(State& s, int station) {
  StationState& st = s.stations[station];
  QueuedFrame& f = st.current;
  const uint16_t duration = f.group ? 0 : Micros(s.phy.sifs_ns + f.rate->ack_ns);
  Transmission& tx = StartTransmission(s, station, FrameKind::kData, f.rate->data, DataPsduBytes(s, f),
                                       f.destination, duration);
  tx.retry = f.data_sent_before;
  tx.sequence_number = f.sequence_number;
  tx.ethernet = f.ethernet;
  ++st.counters.data_tx;
  if (f.data_sent_before) ++st.counters.retries;
  f.data_sent_before = true;
  st.exchange = f.group ? Exchange::kIdle : Exchange::kWaitAck;
}

// ns-3 3.37's WifiMacQueue::WipeAllExpiredMpdus: removes every frame that
// has waited longer than MaxDelay since it was queued. ns-3 calls it when a
// frame arrives at a full queue (WifiMacQueue::Insert) and at every channel
// access (FrameExchangeManager::StartTransmission), where it also removes the
// frame being retried (ns-3 keeps it in the queue): `include_current`.
void DropExpired(State& s, int station, bool include_current) {
  StationState& st = s.stations[station];
  const TimeNs max_delay = s.config.queue_max_delay_ns;
  if (max_delay <= 0) return;
  auto expired = [&](const QueuedFrame& f) { return f.enqueued_ns + max_delay <= s.now_ns; };
  auto drop = [&](const QueuedFrame& f) {
    ++st.counters.queue_drops;
    ++st.counters.queue_expired;
    TraceDrop(s, station, DropReason::kQueueExpired, f.destination, f.sequence_number,
              f.ethernet->size());
  };
  // Frames are queued in arrival order, so the expired ones are a prefix.
  while (!st.queue.empty() && expired(st.queue.front())) {
    drop(st.queue.front());
    st.queue.pop_front();
  }
  if (include_current && st.has_current && expired(st.current)) {
    drop(st.current);
    NextFrame(s, station);  // The contention window stays as it is, as in ns-3.
  }
}

size_t FramesHeld(const StationState& st) { return st.queue.size() + (st.has_current ? 1 : 0); }

}  // namespace

void OnEnqueue(State& s, int station, Bytes ethernet) {
  StationState& st = s.stations[station];
  if (FramesHeld(st) >= s.config.queue_limit_frames) DropExpired(s, station, false);
  if (FramesHeld(st) >= s.config.queue_limit_frames) {
    ++st.counters.queue_drops;
    MacAddress destination;
    std::copy_n(ethernet->begin(), 6, destination.bytes.begin());
    TraceDrop(s, station, DropReason::kQueueFull, destination, 0, ethernet->size());
    return;
  }
  QueuedFrame frame;
  std::copy_n(ethernet->begin(), 6, frame.destination.bytes.begin());
  frame.group = frame.destination.IsGroup();
  frame.ethernet = std::move(ethernet);
  frame.enqueued_ns = s.now_ns;
  frame.use_rts = !frame.group && s.config.rts_threshold_bytes > 0 &&
                  DataMpduBytes(s, frame) > static_cast<int>(s.config.rts_threshold_bytes);
  st.queue.push_back(std::move(frame));
  if (!st.has_current) {
    NextFrame(s, station);
    RequestAccess(s, station);
  }
}

void StartCurrentFrame(State& s, int station) {
  StationState& st = s.stations[station];
  DropExpired(s, station, true);
  if (!st.has_current) {
    // Everything expired: release the channel with a new backoff (ns-3's
    // Txop::NotifyChannelReleased -> GenerateBackoff).
    StartBackoff(s, station);
    return;
  }
  QueuedFrame& f = st.current;
  ChooseRates(s, station);
  if (!f.use_rts) {
    SendData(s, station);
    return;
  }
  // RTS Duration: CTS + DATA + ACK + 3 SIFS (9.3.1.2). RTS at the control
  // rate of the DATA rate (or Ideal's RTS rate); CTS answers at the control
  // rate of the RTS's.
  const uint16_t duration =
      Micros(3 * s.phy.sifs_ns + f.rts_rate->cts_ns + DataDurationNs(s, f) + f.rate->ack_ns);
  const ModeEntry& rts_mode = s.config.rate_control == MediumConfig::RateControl::kIdeal
                                  ? f.rts_rate->data
                                  : f.rts_rate->control;
  StartTransmission(s, station, FrameKind::kRts, rts_mode, kRtsBytes, f.destination, duration);
  ++st.counters.rts_tx;
  st.exchange = Exchange::kWaitCts;
}

void OnOwnTxEnd(State& s, const Transmission& tx) {
  StationState& st = s.stations[tx.source];
  if (tx.kind == FrameKind::kData && tx.group) {
    ++st.counters.sent_ok;
    FinishCurrent(s, tx.source);
    return;
  }
  if ((tx.kind == FrameKind::kData && st.exchange == Exchange::kWaitAck) ||
      (tx.kind == FrameKind::kRts && st.exchange == Exchange::kWaitCts)) {
    ++st.timeout_generation;
    st.timeout_waits_for_rx = false;
    // ns-3's AckTimeout/CtsTimeout (10.3.2.9): SIFS + slot + aRxPHYStartDelay,
    // the PHY preamble and header of the expected response.
    const TimeNs timeout_ns =
        s.phy.sifs_ns + s.phy.slot_ns +
        RateFor(s, tx.mode->mode).control.header.preamble_and_header_ns;
    s.scheduler.Push(s.now_ns + timeout_ns, EventType::kTimeout, tx.source, st.timeout_generation);
  }
}

void OnFrameReceived(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  StationState& st = s.stations[station];
  const bool for_me = tx.ra == st.mac;
  switch (tx.kind) {
    case FrameKind::kData: {
      if (!tx.group && !for_me) return;
      if (!tx.group) {
        ScheduleResponse(s, station, FrameKind::kAck, tx.ta, 0,
                         &RateFor(s, tx.mode->mode), entry.sinr);
        auto& last = st.last_sequence_from;
        if (static_cast<int>(last.size()) <= tx.source) last.resize(tx.source + 1, -1);
        if (tx.retry && last[tx.source] == tx.sequence_number) {
          ++st.counters.rx_duplicates;
          return;
        }
        last[tx.source] = tx.sequence_number;
      }
      ++st.counters.rx_delivered;
      if (s.deliveries != nullptr) {
        s.deliveries->push_back(Delivery{station, tx.source, *tx.ethernet, s.now_ns,
                                         entry.power_dbm, 10 * std::log10(entry.sinr)});
      }
      return;
    }
    case FrameKind::kRts:
      // Answer only with an idle NAV (10.3.2.7).
      if (for_me && st.nav_until_ns <= s.now_ns) {
        const RateEntry& rts_rate = RateFor(s, tx.mode->mode);
        const TimeNs rest = tx.duration_us * kNsPerUs - s.phy.sifs_ns - rts_rate.cts_ns;
        ScheduleResponse(s, station, FrameKind::kCts, tx.ta, Micros(std::max<TimeNs>(rest, 0)),
                         &rts_rate, entry.sinr);
      }
      return;
    case FrameKind::kCts:
      if (for_me && st.exchange == Exchange::kWaitCts) {
        ++st.timeout_generation;
        st.timeout_waits_for_rx = false;
        st.exchange = Exchange::kIdle;
        st.short_retry_count = 0;  // ns-3 ReportRtsOk.
        ReportSnr(s, station, tx.ta, tx.reported_snr);
        ScheduleResponse(s, station, FrameKind::kData, st.current.destination, 0);
      }
      return;
    case FrameKind::kAck:
      if (for_me && st.exchange == Exchange::kWaitAck) {
        ++st.timeout_generation;
        st.timeout_waits_for_rx = false;
        ++st.counters.sent_ok;
        (st.current.use_rts ? st.long_retry_count : st.short_retry_count) = 0;
        ReportSnr(s, station, tx.ta, tx.reported_snr);  // ns-3 ReportDataOk.
        FinishCurrent(s, station);
      }
      return;
  }
}

void OnLockedRxEnd(State& s, int station) {
  StationState& st = s.stations[station];
  if (st.timeout_waits_for_rx && st.exchange != Exchange::kIdle) ExchangeFailed(s, station);
  st.timeout_waits_for_rx = false;
}

void OnTimeout(State& s, int station, uint64_t generation) {
  StationState& st = s.stations[station];
  if (generation != st.timeout_generation || st.exchange == Exchange::kIdle) return;
  if (st.rx.tx >= 0) {
    // A frame started before the timeout: it may be the response (ns-3 waits too).
    st.timeout_waits_for_rx = true;
    return;
  }
  st.timeout_end_ns = s.now_ns;
  ExchangeFailed(s, station);
}

void OnRespond(State& s, int station) {
  StationState& st = s.stations[station];
  if (!st.response_pending) return;
  st.response_pending = false;
  if (st.transmitting_tx >= 0) return;
  switch (st.response_kind) {
    case FrameKind::kAck:
      StartTransmission(s, station, FrameKind::kAck, st.response_rate->control, kAckBytes,
                        st.response_ra, 0)
          .reported_snr = st.response_snr;
      ++st.counters.ack_tx;
      return;
    case FrameKind::kCts:
      StartTransmission(s, station, FrameKind::kCts, st.response_rate->control, kCtsBytes,
                        st.response_ra, st.response_duration_us)
          .reported_snr = st.response_snr;
      ++st.counters.cts_tx;
      return;
    case FrameKind::kData:
      if (st.has_current) SendData(s, station);
      return;
    case FrameKind::kRts:
      return;
  }
}

}  // namespace sitlnet::mac

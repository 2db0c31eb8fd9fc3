// Frame exchange (IEEE 802.11-2016 10.3.2.5-10.3.2.11, 10.3.4.4, 10.22.2): queues per
// access category, DATA/ACK and RTS/CTS/DATA/ACK sequences, EDCA TXOPs (further frames SIFS
// apart, a CF-End at the end), internal collisions, ACK/CTS timeouts (ns-3: SIFS + slot + PHY
// preamble/header), retries with short/long retry counters and binary exponential backoff,
// duplicate filtering by (TA, TID, sequence number). The Block Ack exchanges (A-MPDU, BlockAckReq,
// ADDBA) are in ampdu_exchange.cc.
#include <algorithm>
#include <cmath>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {

uint16_t DurationFieldUs(TimeNs ns) {
  return static_cast<uint16_t>((ns + kNsPerUs - 1) / kNsPerUs);
}

int DataMpduBytes(const State& s, const QueuedFrame& frame) {
  if (frame.type != MpduType::kData) return kAddbaBytes;
  return MpduBytesForEthernet(static_cast<int>(frame.ethernet->size()), s.phy.qos);
}

namespace {

// The counter a frame's sequence number comes from. Action frames count apart, as ns-3's
// non-QoS frames do; where Block Ack agreements may form (UsesBlockAck) QoS Data frames count
// per receiver and TID.
uint16_t& SequenceCounter(State& s, int station, const MacAddress& receiver, int tid,
                          MpduType type, bool group) {
  StationState& st = s.stations[station];
  if (type != MpduType::kData) return st.next_management_sequence;
  if (!UsesBlockAck(s) || group) return st.next_sequence_number[tid];
  for (ReceiverSequences& r : st.receiver_sequences) {
    if (r.receiver == receiver) return r.next[tid];
  }
  st.receiver_sequences.push_back(ReceiverSequences{receiver, {}});
  return st.receiver_sequences.back().next[tid];
}

}  // namespace

// Without Block Ack (UsesBlockAck false) a frame gets its number when it is taken into service
// (as before: the golden test pins it); with it when it is first sent. A frame that goes back
// to the queue (Block Ack retransmissions) keeps its own.
void AssignSequence(State& s, int station, QueuedFrame& f) {
  if (f.sequence_assigned) return;
  f.sequence_assigned = true;
  uint16_t& next = SequenceCounter(s, station, f.destination, f.tid, f.type, f.group);
  f.sequence_number = next;
  next = static_cast<uint16_t>((next + 1) & 0x0fff);
}

uint16_t PeekSequence(State& s, int station, const MacAddress& receiver, int tid) {
  return SequenceCounter(s, station, receiver, tid, MpduType::kData, false);
}

namespace {

constexpr MacAddress kBroadcastMac{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

size_t EthernetBytes(const QueuedFrame& f) { return f.ethernet ? f.ethernet->size() : 0; }

// Management frames go at the lowest basic rate (ns-3 3.37's GetDataTxVector for IsMgt()).
const RateEntry* ManagementRate(const State& s) {
  for (const RateEntry& r : s.rates) {
    if (r.basic) return &r;
  }
  return &s.rates.front();
}

// The PSDU of the current attempt (its rate chosen): a VHT one is an S-MPDU.
int DataPsduBytes(const State& s, const QueuedFrame& frame) {
  const bool vht = frame.rate->data.mode.format == PhyFormat::kVht;
  return DataMpduBytes(s, frame) + (vht ? kMpduDelimiterBytes : 0);
}

TimeNs DataDurationNs(const State& s, const QueuedFrame& frame) {
  return PpduDurationNs(frame.rate->data.mode, frame.rate->data.header, DataPsduBytes(s, frame));
}

}  // namespace

void TraceDrop(State& s, int station, DropReason reason, const MacAddress& destination,
               std::optional<uint16_t> sequence_number, size_t bytes) {
  if (!s.trace_enabled) return;
  TraceEvent event;
  event.drop = DropRecord{s.now_ns, station, reason, destination, sequence_number.value_or(0),
                          bytes,    sequence_number.has_value()};
  s.trace.push_back(std::move(event));
}

std::optional<uint16_t> SequenceNumberOf(const QueuedFrame& f) {
  if (!f.sequence_assigned) return std::nullopt;
  return f.sequence_number;
}

namespace {

AccessFunction& Exchanging(State& s, int station) {
  StationState& st = s.stations[station];
  return st.acs[st.exchange_ac];
}

}  // namespace

// ns-3's QosTxop::GetRemainingTxop.
TimeNs RemainingTxopNs(const State& s, const AccessFunction& f, int ac) {
  return std::max<TimeNs>(f.txop_start_ns + s.phy.edca[ac].txop_limit_ns - s.now_ns, 0);
}

// Takes the next queued frame of `ac` into service, if any.
void NextFrame(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  f.has_current = false;
  if (f.queue.empty()) return;
  f.current = std::move(f.queue.front());
  f.queue.pop_front();
  f.has_current = true;
  if (!UsesBlockAck(s)) AssignSequence(s, station, f.current);
}

namespace {

// The frame in service is done (acknowledged, sent to a group, or dropped):
// reset CW, end the TXOP, and run a post-backoff (10.3.4.3) carrying the next frame if any.
// `current_done` false: a Block Ack left the frame in service unacknowledged; it stays.
void FinishCurrent(State& s, int station, int ac, bool current_done = true) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  st.exchange = Exchange::kIdle;
  f.cw = s.phy.edca[ac].cw_min;
  f.txop_start_ns = -1;
  if (current_done) NextFrame(s, station, ac);
  StartBackoff(s, station, ac);
}

}  // namespace

// With time left in its TXOP the access category sends its next frame a SIFS later
// (10.22.2.8; ns-3 3.37's QosFrameExchangeManager::TransmissionSucceeded).
void ExchangeSucceeded(State& s, int station, bool current_done) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& f = st.acs[ac];
  if (f.txop_start_ns < 0 || RemainingTxopNs(s, f, ac) <= s.phy.sifs_ns) {
    FinishCurrent(s, station, ac, current_done);
    return;
  }
  st.exchange = Exchange::kIdle;
  f.cw = s.phy.edca[ac].cw_min;
  if (current_done) NextFrame(s, station, ac);
  s.scheduler.Push(s.now_ns + s.phy.sifs_ns, EventType::kContinueTxop, station,
                   static_cast<uint64_t>(ac));
}

namespace {

void ExchangeFailed(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  const bool was_cts = st.exchange == Exchange::kWaitCts;
  const bool was_block_ack = st.exchange == Exchange::kWaitBlockAck;
  st.exchange = Exchange::kIdle;
  st.timeout_waits_for_rx = false;
  ++st.counters.tx_failures;
  // A failure ends the TXOP: the initial frame's as the standard says (10.22.2.2), a later
  // one's too here (ns-3 3.37 may instead resume after PIFS: docs/mac_phy_sim.md).
  af.txop_start_ns = -1;
  if (was_block_ack) {
    BlockAckMissed(s, station);
    return;
  }
  QueuedFrame& f = af.current;
  // A missed ACK takes it out of flight under an agreement (ns-3's NotifyMissedAck): a
  // BlockAckReq owed does not wait for it.
  if (!was_cts) f.in_flight = false;
  // Station retry counts (10.3.4.4): SRC for RTS and short DATA, LRC for DATA
  // after a CTS; at the limit the frame in service is discarded.
  const bool data_after_cts = !was_cts && f.use_rts;
  int& count = data_after_cts ? af.long_retry_count : af.short_retry_count;
  ++count;
  const int limit = data_after_cts ? s.config.long_retry_limit : s.config.short_retry_limit;
  // ns-3 3.37's NormalAckTimeout / DoCtsTimeout: report the failure, then ask the rate
  // manager whether to retry (Minstrel answers by its retry chain, not the limit).
  RateManager& rates = *st.rate_manager;
  if (was_cts) {
    rates.ReportRtsFailed(f.destination, s.now_ns);
  } else {
    rates.ReportDataFailed(f.destination, s.now_ns);
  }
  if (!rates.NeedRetransmission(f.destination, count < limit, s.now_ns)) {
    count = 0;
    if (was_cts) {
      rates.ReportFinalRtsFailed(f.destination, s.now_ns);
    } else {
      rates.ReportFinalDataFailed(f.destination, s.now_ns);
    }
    ++st.counters.lost_retry_limit;
    TraceDrop(s, station, DropReason::kRetryLimit, f.destination, SequenceNumberOf(f),
              EthernetBytes(f));
    OnMpduDiscarded(s, station, f);
    FinishCurrent(s, station, ac);
    return;
  }
  af.cw = std::min(2 * af.cw + 1, s.phy.edca[ac].cw_max);
  StartBackoff(s, station, ac);
}

}  // namespace

void ScheduleResponse(State& s, int station, FrameKind kind, const MacAddress& ra,
                      uint16_t duration_us, const RateEntry* answered, double snr) {
  StationState& st = s.stations[station];
  st.response_rate = answered;
  st.response_snr = snr;
  st.response_pending = true;
  st.response_kind = kind;
  st.response_ra = ra;
  st.response_duration_us = duration_us;
  s.scheduler.Push(s.now_ns + s.phy.sifs_ns, EventType::kRespond, station, 0);
}

namespace {

void SendData(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  AssignSequence(s, station, f);
  if (TrySendAmpdu(s, station)) return;
  const TimeNs ack_time_ns = f.group ? 0 : s.phy.sifs_ns + f.rate->ack_ns;
  TimeNs duration_ns = ack_time_ns;
  if (af.txop_start_ns >= 0) {
    // Within a TXOP the Duration covers what is left of it (9.2.5.2; ns-3's
    // QosFrameExchangeManager::GetFrameDurationId).
    duration_ns = std::max(RemainingTxopNs(s, af, ac) - DataDurationNs(s, f), ack_time_ns);
  }
  const bool action = f.type != MpduType::kData;
  Transmission& tx =
      StartTransmission(s, station, action ? FrameKind::kAction : FrameKind::kData, f.rate->data,
                        DataPsduBytes(s, f), f.destination, DurationFieldUs(duration_ns));
  tx.retry = f.data_sent_before;
  tx.sequence_number = f.sequence_number;
  tx.tid = f.tid;
  tx.ethernet = f.ethernet;
  if (action) {
    tx.addba_response = f.type == MpduType::kAddbaResponse;
    if (!tx.addba_response) {
      tx.ba_ssn = f.ba_ssn;
      if (!f.data_sent_before) OnAddbaRequestSent(s, station, f.destination, f.tid);
    }
    ++st.counters.addba_tx;
    f.data_sent_before = true;
    st.exchange = Exchange::kWaitAck;
    return;
  }
  ++st.counters.data_tx;
  if (f.data_sent_before) ++st.counters.retries;
  f.data_sent_before = true;
  f.in_flight = true;
  st.exchange = f.group ? Exchange::kIdle : Exchange::kWaitAck;
}

// RTS, SIFS, CTS, SIFS before the DATA of `f` (ns-3's protection time).
TimeNs RtsCtsNs(const State& s, const QueuedFrame& f) {
  return PpduDurationNs(f.rts_mode->mode, f.rts_mode->header, kRtsBytes) + 2 * s.phy.sifs_ns +
         f.rts_rate->cts_ns;
}

// ChooseRates, and the lowest basic rate for an action frame. With aggregation the A-MPDU is
// planned now, and RTS/CTS protects it when the whole PSDU is longer than rts_threshold_bytes:
// ns-3 3.37 compares the PSDU's size as each MPDU joins (WifiDefaultProtectionManager::TryAddMpdu
// -> GetSizeIfAddMpdu, wifi-default-protection-manager.cc:95-96; NeedRts,
// wifi-remote-station-manager.cc:1093). Without aggregation each MPDU is compared, as before.
void ChooseFrameRates(State& s, int station) {
  ChooseRates(s, station);
  QueuedFrame& f = Exchanging(s, station).current;
  if (f.type != MpduType::kData) {
    f.rate = f.rts_rate = ManagementRate(s);
    f.use_rts = false;
  } else if (s.config.aggregation && !f.group && s.config.rts_threshold_bytes > 0) {
    f.ampdu_bytes = PlannedAmpduBytes(s, station, RtsCtsNs(s, f));
    const int psdu_bytes = f.ampdu_bytes > 0 ? f.ampdu_bytes : DataMpduBytes(s, f);
    f.use_rts = psdu_bytes > static_cast<int>(s.config.rts_threshold_bytes);
  }
}

// RTS (if the frame needs one) or DATA of the frame in service of exchange_ac.
void SendCurrent(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  ChooseFrameRates(s, station);
  if (!f.use_rts) {
    SendData(s, station);
    return;
  }
  const ModeEntry& rts_mode = *f.rts_mode;
  // RTS Duration: CTS + DATA + ACK + 3 SIFS (9.3.1.2). RTS at the control
  // rate of the DATA rate (or Ideal's RTS rate); CTS answers at the control
  // rate of the RTS's. Within a TXOP: the rest of the TXOP (ns-3's GetRtsDurationId).
  // An A-MPDU's: its PPDU and the BlockAck instead.
  const TimeNs data_and_answer_ns = f.ampdu_bytes > 0 ? AmpduAndBlockAckNs(f, f.ampdu_bytes)
                                                      : DataDurationNs(s, f) + f.rate->ack_ns;
  TimeNs duration_ns = 3 * s.phy.sifs_ns + f.rts_rate->cts_ns + data_and_answer_ns;
  if (af.txop_start_ns >= 0) {
    duration_ns = RemainingTxopNs(s, af, ac) -
                  PpduDurationNs(rts_mode.mode, rts_mode.header, kRtsBytes);
    duration_ns = std::max<TimeNs>(duration_ns, 0);
  }
  StartTransmission(s, station, FrameKind::kRts, rts_mode, kRtsBytes, f.destination,
                    DurationFieldUs(duration_ns));
  ++st.counters.rts_tx;
  st.exchange = Exchange::kWaitCts;
}

}  // namespace

// ns-3 3.37's WifiMacQueue::WipeAllExpiredMpdus: removes every frame that
// has waited longer than MaxDelay since it was queued. ns-3 calls it when a
// frame arrives at a full queue (WifiMacQueue::Insert) and at every channel
// access (FrameExchangeManager::StartTransmission), where it also removes the
// frame being retried (ns-3 keeps it in the queue): `include_current`.
void DropExpired(State& s, int station, int ac, bool include_current) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  const TimeNs max_delay = s.config.queue_max_delay_ns;
  if (max_delay <= 0) return;
  auto expired = [&](const QueuedFrame& f) { return f.enqueued_ns + max_delay <= s.now_ns; };
  auto drop = [&](const QueuedFrame& f) {
    ++st.counters.queue_drops;
    ++st.counters.queue_expired;
    TraceDrop(s, station, DropReason::kQueueExpired, f.destination, SequenceNumberOf(f),
              EthernetBytes(f));
  };
  // Data frames are queued in arrival order (retransmissions go back to the head in order), so
  // the expired ones are a prefix, but for action frames put at the head later (an ADDBA
  // Response), which must not shield older frames.
  for (auto it = af.queue.begin(); it != af.queue.end();) {
    if (expired(*it)) {
      drop(*it);
      OnMpduDiscarded(s, station, *it);
      it = af.queue.erase(it);
    } else if (it->type != MpduType::kData) {
      ++it;
    } else {
      break;
    }
  }
  if (include_current && af.has_current && expired(af.current)) {
    drop(af.current);
    OnMpduDiscarded(s, station, af.current);
    NextFrame(s, station, ac);  // The contention window stays as it is, as in ns-3.
  }
}

namespace {

// What the category holds against queue_limit_frames: queued, in service, in an A-MPDU under
// way (ns-3's WifiMacQueue keeps in-flight MPDUs).
size_t FramesHeld(const AccessFunction& f) {
  return f.queue.size() + (f.has_current ? 1 : 0) + f.ampdu_rest.size();
}

// Whether expired frames go at every arrival, as on an ns-3 3.37 QoS station, the frame in
// service included while it waits for access (WaitsForAccess). Only on 802.11ac stations
// without aggregation: their single MPDUs sent at the edge of their lifetime expire in flight
// and owe a BlockAckReq a SIFS after the ACK, and the room a wipe makes decides how many are
// sent so (docs/mac_phy_sim.md, "802.11ac without A-MPDU"). a/b/g and 802.11n stations without
// aggregation drop such frames at the next access, as before (the same throughput; the golden
// test keeps their bytes). A-MPDU stations too, for now: the change moved their several-sender
// cells by up to 4 % either way at 3 seeds (docs/validation.md).
bool WipesAtEveryArrival(const State& s) { return UsesBlockAck(s) && !s.config.aggregation; }

// Whether an exchange holds the frame in service of `ac`: on the air (a group frame, or an
// exchange of `ac` under way) or its DATA due a SIFS after the CTS its RTS got. ns-3 3.37's
// frame exchange manager sends the PSDU it holds even when a wipe took it out of the
// WifiMacQueue (WifiMacQueue::Insert only removes it from the queue).
bool HeldByExchange(const State& s, int station, int ac) {
  const StationState& st = s.stations[station];
  if (st.exchange_ac != ac) return false;
  return st.exchange != Exchange::kIdle || st.transmitting_tx >= 0 ||
         (st.response_pending && st.response_kind == FrameKind::kData);
}

// Whether the frame in service of `ac` waits for channel access: not sent yet, or waiting to be
// retried, no exchange holding it. ns-3 3.37 keeps that frame in its WifiMacQueue, whose wipes
// take it when it expired (WifiMacQueueContainer::DoExtractExpiredMpdus takes every expired MPDU
// at the queue's head), making room for the frame arriving.
bool WaitsForAccess(const State& s, int station, int ac) {
  return s.stations[station].acs[ac].has_current && !HeldByExchange(s, station, ac);
}

// Releases the TXOP of `ac` and draws a new backoff (ns-3's NotifyChannelReleased).
void ReleaseTxop(State& s, int station, int ac) {
  s.stations[station].acs[ac].txop_start_ns = -1;
  StartBackoff(s, station, ac);
}

}  // namespace

void OnEnqueue(State& s, int station, Bytes ethernet) {
  StationState& st = s.stations[station];
  const int tid = s.phy.qos ? UserPriorityOf(*ethernet) : 0;
  const int ac = AccessFunctionFor(s, tid);
  AccessFunction& af = st.acs[ac];
  // ns-3 3.37 wipes expired frames when one arrives at a full queue (WifiMacQueue::Insert). A
  // QoS station wipes at every arrival too (Txop::Queue asks QosTxop::HasFramesToTransmit,
  // qos-txop.cc:315-326, which wipes); here only where that decides how many single MPDUs
  // expire in flight and owe a BlockAckReq (WipesAtEveryArrival).
  size_t expired_in_flight = 0;
  const bool queue_full = FramesHeld(af) >= s.config.queue_limit_frames;
  if (WipesAtEveryArrival(s) || queue_full) {
    // The frame in service is in ns-3's queue too: with aggregation (at a full queue) and on
    // 802.11ac without it (at every arrival) it goes if it expired while it waits for access.
    const bool wipe_current = WipesAtEveryArrival(s) || (queue_full && s.config.aggregation);
    const bool current_waits = WaitsForAccess(s, station, ac);
    DropExpired(s, station, ac, wipe_current && current_waits);
    expired_in_flight = ExpireInFlight(s, station, ac);
    // Held by an exchange (a group frame on the air, DATA due a SIFS after its CTS), ns-3 takes
    // the expired frame out of its queue yet sends it: room, but it stays in service.
    if (wipe_current && !current_waits && expired_in_flight == 0 && af.has_current &&
        s.config.queue_max_delay_ns > 0 &&
        af.current.enqueued_ns + s.config.queue_max_delay_ns <= s.now_ns) {
      expired_in_flight = 1;
    }
  }
  if (FramesHeld(af) - expired_in_flight >= s.config.queue_limit_frames) {
    ++st.counters.queue_drops;
    MacAddress destination;
    std::copy_n(ethernet->begin(), 6, destination.bytes.begin());
    TraceDrop(s, station, DropReason::kQueueFull, destination, std::nullopt, ethernet->size());
    return;
  }
  QueuedFrame frame;
  std::copy_n(ethernet->begin(), 6, frame.destination.bytes.begin());
  frame.group = frame.destination.IsGroup();
  frame.tid = static_cast<uint8_t>(tid);
  frame.ethernet = std::move(ethernet);
  frame.enqueued_ns = s.now_ns;
  frame.use_rts = !frame.group && s.config.rts_threshold_bytes > 0 &&
                  DataMpduBytes(s, frame) > static_cast<int>(s.config.rts_threshold_bytes);
  af.queue.push_back(std::move(frame));
  if (!af.has_current) {
    NextFrame(s, station, ac);
    RequestAccess(s, station, ac);
  }
}

bool StartCurrentFrame(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  st.exchange_ac = ac;
  DropExpired(s, station, ac, true);
  if (!af.has_current) {
    // A BlockAckReq owed goes alone; else everything expired: release the channel with a new
    // backoff (ns-3's Txop::NotifyChannelReleased -> GenerateBackoff).
    if (HasBlockAckReqToSend(s, station, ac)) return PrepareBlockAckExchange(s, station, ac);
    StartBackoff(s, station, ac);
    return false;
  }
  // A TXOP starts with the access (ns-3's QosTxop::NotifyChannelAccessed).
  if (s.phy.edca[ac].txop_limit_ns > 0) af.txop_start_ns = s.now_ns;
  if (PrepareBlockAckExchange(s, station, ac)) return true;
  SendCurrent(s, station);
  return true;
}

void OnInternalCollision(State& s, int station, int ac) {
  // 10.22.2.11.2: the losing EDCAF acts as after a failed transmission: its retry count grows
  // and its CW doubles, or its frame is discarded at the retry limit (ns-3 3.37's
  // FrameExchangeManager::NotifyInternalCollision, which counts the long retry count for a
  // frame that needs RTS); then a new backoff.
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  ++st.counters.internal_collisions;
  const QueuedFrame& f = af.current;
  if (af.has_current && !f.group) {
    int& count = f.use_rts ? af.long_retry_count : af.short_retry_count;
    const int limit = f.use_rts ? s.config.long_retry_limit : s.config.short_retry_limit;
    RateManager& rates = *st.rate_manager;
    rates.ReportDataFailed(f.destination, s.now_ns);
    if (!rates.NeedRetransmission(f.destination, ++count < limit, s.now_ns)) {
      count = 0;
      rates.ReportFinalDataFailed(f.destination, s.now_ns);
      ++st.counters.lost_retry_limit;
      TraceDrop(s, station, DropReason::kRetryLimit, f.destination, SequenceNumberOf(f),
                EthernetBytes(f));
      OnMpduDiscarded(s, station, f);
      af.cw = s.phy.edca[ac].cw_min;
      NextFrame(s, station, ac);
      StartBackoff(s, station, ac);
      return;
    }
  }
  af.cw = std::min(2 * af.cw + 1, s.phy.edca[ac].cw_max);
  StartBackoff(s, station, ac);
}

void OnContinueTxop(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  if (af.txop_start_ns < 0) return;
  if (st.transmitting_tx >= 0 || st.exchange != Exchange::kIdle) {
    ReleaseTxop(s, station, ac);
    return;
  }
  st.exchange_ac = ac;
  DropExpired(s, station, ac, true);
  const TimeNs remaining_ns = RemainingTxopNs(s, af, ac);
  // A BlockAckReq owed goes first if it fits (ns-3's StartFrameExchange, SendMpduFromBaManager).
  if (PrepareBlockAckExchange(s, station, ac, remaining_ns)) return;
  if (af.has_current) {
    // The next frame goes if its exchange fits in what is left (ns-3's TryAddMpdu: PPDU
    // duration <= remaining - protection - SIFS - ACK).
    QueuedFrame& f = af.current;
    ChooseFrameRates(s, station);
    TimeNs needed_ns = DataDurationNs(s, f);
    if (!f.group) needed_ns += s.phy.sifs_ns + f.rate->ack_ns;
    if (f.use_rts) {
      const ModeEntry& rts_mode = *f.rts_mode;
      needed_ns += PpduDurationNs(rts_mode.mode, rts_mode.header, kRtsBytes) +
                   2 * s.phy.sifs_ns + f.rts_rate->cts_ns;
    }
    if (needed_ns <= remaining_ns) {
      SendCurrent(s, station);
      return;
    }
  }
  // Not enough time (or nothing left): a CF-End gives the rest back if it fits (ns-3 3.37's
  // SendCfEndIfNeeded; at the non-unicast rate), and the TXOP ends when it does.
  const ModeEntry& mode = s.group_rate->data;
  if (remaining_ns > PpduDurationNs(mode.mode, mode.header, kCfEndBytes)) {
    StartTransmission(s, station, FrameKind::kCfEnd, mode, kCfEndBytes, kBroadcastMac, 0);
    ++st.counters.cf_end_tx;
    return;
  }
  ReleaseTxop(s, station, ac);
}

void OnOwnTxEnd(State& s, const Transmission& tx) {
  StationState& st = s.stations[tx.source];
  if (tx.kind == FrameKind::kCfEnd) {
    ReleaseTxop(s, tx.source, st.exchange_ac);
    return;
  }
  if (tx.kind == FrameKind::kData && tx.group) {
    ++st.counters.sent_ok;
    ExchangeSucceeded(s, tx.source);
    return;
  }
  const bool data_like = tx.kind == FrameKind::kData || tx.kind == FrameKind::kAction;
  if ((data_like && st.exchange == Exchange::kWaitAck) ||
      ((tx.kind == FrameKind::kData || tx.kind == FrameKind::kBlockAckReq) &&
       st.exchange == Exchange::kWaitBlockAck) ||
      (tx.kind == FrameKind::kRts && st.exchange == Exchange::kWaitCts)) {
    ++st.timeout_generation;
    st.timeout_waits_for_rx = false;
    // ns-3's AckTimeout/CtsTimeout (10.3.2.9): SIFS + slot + aRxPHYStartDelay,
    // the PHY preamble and header of the expected response (BlockAckTimeout alike).
    const TimeNs timeout_ns =
        s.phy.sifs_ns + s.phy.slot_ns +
        RateFor(s, tx.mode->mode).control.header.preamble_and_header_ns;
    s.scheduler.Push(s.now_ns + timeout_ns, EventType::kTimeout, tx.source, st.timeout_generation);
    // The other access functions count from its end (ns-3's NotifyAckTimeoutStartNow).
    st.timeout_end_ns = s.now_ns + timeout_ns;
    RescheduleAccess(s, tx.source);
  }
}

// The response came: the timeout no longer holds channel access back
// (ns-3's NotifyAckTimeoutResetNow / NotifyCtsTimeoutResetNow).
void EndTimeout(State& s, int station) {
  StationState& st = s.stations[station];
  ++st.timeout_generation;
  st.timeout_waits_for_rx = false;
  if (st.timeout_end_ns > s.now_ns) {
    st.timeout_end_ns = s.now_ns;
    RescheduleAccess(s, station);
  }
}

void OnFrameReceived(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  StationState& st = s.stations[station];
  const bool for_me = tx.ra == st.mac;
  switch (tx.kind) {
    case FrameKind::kData: {
      if (!tx.group && !for_me) return;
      if (!tx.group && !tx.subframes.empty()) {
        ReceiveAmpdu(s, station, tx, entry);
        return;
      }
      if (!tx.group) {
        // ACK Duration: the DATA's less SIFS and the ACK (9.2.5.7): 0 outside a TXOP.
        const RateEntry& answered = RateFor(s, tx.mode->mode);
        const TimeNs rest_ns = tx.duration_us * kNsPerUs - s.phy.sifs_ns - answered.ack_ns;
        ScheduleResponse(s, station, FrameKind::kAck, tx.ta,
                         rest_ns >= kNsPerUs ? DurationFieldUs(rest_ns) : 0, &answered, entry.sinr);
        if (BaRecipient* agreement = RecipientAgreement(s, station, tx.source, tx.tid)) {
          ReceiveUnderAgreement(s, station, *agreement, tx.sequence_number, tx.ethernet,
                                entry.power_dbm, entry.sinr);
          return;
        }
        auto& last = st.last_sequence_from;
        const size_t key = static_cast<size_t>(tx.source) * 8 + tx.tid;
        if (last.size() <= key) last.resize((static_cast<size_t>(tx.source) + 1) * 8, -1);
        if (tx.retry && last[key] == tx.sequence_number) {
          ++st.counters.rx_duplicates;
          return;
        }
        last[key] = tx.sequence_number;
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
        ScheduleResponse(s, station, FrameKind::kCts, tx.ta, DurationFieldUs(std::max<TimeNs>(rest, 0)),
                         &rts_rate, entry.sinr);
      }
      return;
    case FrameKind::kCts:
      if (for_me && st.exchange == Exchange::kWaitCts) {
        EndTimeout(s, station);
        st.exchange = Exchange::kIdle;
        Exchanging(s, station).short_retry_count = 0;  // ns-3 ReportRtsOk.
        st.rate_manager->ReportRtsOk(tx.ta, tx.reported_snr);
        ScheduleResponse(s, station, FrameKind::kData, Exchanging(s, station).current.destination,
                         0);
      }
      return;
    case FrameKind::kAck:
      if (for_me && st.exchange == Exchange::kWaitAck) {
        EndTimeout(s, station);
        ++st.counters.sent_ok;
        AccessFunction& af = Exchanging(s, station);
        (af.current.use_rts ? af.long_retry_count : af.short_retry_count) = 0;
        st.rate_manager->ReportDataOk(tx.ta, tx.reported_snr, s.now_ns);
        OnActionAcked(s, station, af.current);
        // Under an agreement the MPDU may have expired in flight and owe a BlockAckReq.
        if (BlockAckReqFollows(s, station, true)) return;
        ExchangeSucceeded(s, station);
      }
      return;
    case FrameKind::kCfEnd:
      return;  // Its NAV reset happens where the NAV is set (transmission.cc).
    case FrameKind::kAction:
      if (for_me) ReceiveAction(s, station, tx, entry);
      return;
    case FrameKind::kBlockAckReq:
      if (for_me) {
        ReceiveBlockAckReqFrame(s, station, tx, entry);
      }
      return;
    case FrameKind::kBlockAck:
      if (for_me && st.exchange == Exchange::kWaitBlockAck) {
        EndTimeout(s, station);
        ReceiveBlockAck(s, station, tx);
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
                        st.response_ra, st.response_duration_us)
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
      if (Exchanging(s, station).has_current) SendData(s, station);
      return;
    case FrameKind::kBlockAck:
      SendBlockAck(s, station);
      return;
    case FrameKind::kRts:
    case FrameKind::kCfEnd:
    case FrameKind::kBlockAckReq:
    case FrameKind::kAction:
      return;
  }
}

}  // namespace sitlnet::mac

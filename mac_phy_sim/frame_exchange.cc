// Frame exchange (IEEE 802.11-2016 10.3.2.5-10.3.2.11, 10.3.4.4, 10.22.2): queues per
// access category, DATA/ACK and RTS/CTS/DATA/ACK sequences, EDCA TXOPs (further frames SIFS
// apart, a CF-End at the end), internal collisions, ACK/CTS timeouts (ns-3: SIFS + slot + PHY
// preamble/header), retries with short/long retry counters and binary exponential backoff,
// duplicate filtering by (TA, TID, sequence number).
#include <algorithm>
#include <cmath>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

uint16_t Micros(TimeNs ns) { return static_cast<uint16_t>((ns + kNsPerUs - 1) / kNsPerUs); }

constexpr MacAddress kBroadcastMac{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

int DataMpduBytes(const State& s, const QueuedFrame& frame) {
  if (frame.type != MpduType::kData) return kAddbaBytes;
  return MpduBytesForEthernet(static_cast<int>(frame.ethernet->size()), s.phy.qos);
}

size_t EthernetBytes(const QueuedFrame& f) { return f.ethernet ? f.ethernet->size() : 0; }

int SequenceDistance(uint16_t from, uint16_t to) { return (to - from) & 0x0fff; }

// Sequence numbers are given when a frame is first taken from the queue; a frame that goes back
// (Block Ack retransmissions) keeps its own. Action frames count apart, as ns-3's non-QoS ones.
void AssignSequence(StationState& st, QueuedFrame& f) {
  if (f.sequence_assigned) return;
  f.sequence_assigned = true;
  uint16_t& next = f.type == MpduType::kData ? st.next_sequence_number[f.tid]
                                             : st.next_management_sequence;
  f.sequence_number = next;
  next = static_cast<uint16_t>((next + 1) & 0x0fff);
}

// Management frames go at the lowest basic rate (ns-3 3.37's GetDataTxVector for IsMgt()).
const RateEntry* ManagementRate(const State& s) {
  for (const RateEntry& r : s.rates) {
    if (r.basic) return &r;
  }
  return &s.rates.front();
}

// The compressed BlockAck's airtime answering a frame at `answered`'s rate.
TimeNs BlockAckNs(const RateEntry& answered) {
  return PpduDurationNs(answered.control.mode, answered.control.header, kBlockAckBytes);
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

AccessFunction& Exchanging(State& s, int station) {
  StationState& st = s.stations[station];
  return st.acs[st.exchange_ac];
}

// What is left of the TXOP `f` holds (ns-3's QosTxop::GetRemainingTxop), >= 0.
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
  AssignSequence(st, f.current);
}

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

// The exchange of the frame in service succeeded. With time left in its TXOP the access
// category sends its next frame a SIFS later (10.22.2.8; ns-3 3.37's
// QosFrameExchangeManager::TransmissionSucceeded), else it releases the channel.
void ExchangeSucceeded(State& s, int station, bool current_done = true) {
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

// The MPDUs after `current` of an A-MPDU go back to the head of the queue, in order.
void RequeueAmpduRest(AccessFunction& af) {
  for (auto it = af.ampdu_rest.rbegin(); it != af.ampdu_rest.rend(); ++it) {
    af.queue.push_front(std::move(*it));
  }
  af.ampdu_rest.clear();
}

void DropAmpduRest(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  for (const QueuedFrame& f : af.ampdu_rest) {
    ++st.counters.lost_retry_limit;
    TraceDrop(s, station, DropReason::kRetryLimit, f.destination, f.sequence_number,
              EthernetBytes(f));
  }
  af.ampdu_rest.clear();
}

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
  QueuedFrame& f = af.current;
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
    TraceDrop(s, station, DropReason::kRetryLimit, f.destination, f.sequence_number,
              EthernetBytes(f));
    if (f.type == MpduType::kAddbaRequest) {
      OnAddbaRequestDiscarded(s, station, f.destination, f.tid);
    }
    // The MPDUs of an A-MPDU whose BlockAck never came go with it (ns-3's MissedBlockAck
    // without a BlockAckReq to send: docs/mac_phy_sim.md).
    DropAmpduRest(s, station, ac);
    af.bar_pending = false;
    FinishCurrent(s, station, ac);
    return;
  }
  if (was_block_ack) {
    // ns-3 3.37 (UseExplicitBarAfterMissedBlockAck): a BlockAckReq asks what got through; the
    // MPDUs wait in the queue meanwhile, in sequence order.
    if (!af.ampdu_rest.empty()) {
      ReportAmpduTxStatus(s, station, f.destination, 0,
                          1 + static_cast<int>(af.ampdu_rest.size()), f.rate, 0);
    }
    RequeueAmpduRest(af);
    af.bar_pending = true;
  }
  af.cw = std::min(2 * af.cw + 1, s.phy.edca[ac].cw_max);
  StartBackoff(s, station, ac);
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

// Takes from the queue the MPDUs that join `current` in an A-MPDU (ns-3 3.37's
// MpduAggregator::GetNextAmpdu): same receiver and TID, inside the Block Ack window that starts
// at `current`, while the A-MPDU stays within `max_bytes` and its PPDU within 5484 us and what
// is left of the TXOP (less SIFS and the BlockAck). Returns the PSDU length.
int CollectAmpdu(State& s, int station, int ac, uint32_t max_bytes) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  const ModeEntry& mode = f.rate->data;
  TimeNs limit_ns = kMaxPpduDurationNs;
  if (af.txop_start_ns >= 0) {
    limit_ns = std::min(limit_ns,
                        RemainingTxopNs(s, af, ac) - s.phy.sifs_ns - BlockAckNs(*f.rate));
  }
  int bytes = AmpduBytesIfAggregated(0, DataMpduBytes(s, f));
  for (auto it = af.queue.begin();
       it != af.queue.end() && static_cast<int>(af.ampdu_rest.size()) + 1 < kMaxAmpduSubframes;) {
    if (it->type != MpduType::kData || it->tid != f.tid || !(it->destination == f.destination)) {
      ++it;
      continue;
    }
    const uint16_t sequence =
        it->sequence_assigned ? it->sequence_number : st.next_sequence_number[it->tid];
    if (SequenceDistance(f.sequence_number, sequence) >= kBlockAckWindow) break;
    const int with = AmpduBytesIfAggregated(bytes, DataMpduBytes(s, *it));
    if (static_cast<uint32_t>(with) > max_bytes ||
        PpduDurationNs(mode.mode, mode.header, with) > limit_ns) {
      break;
    }
    bytes = with;
    AssignSequence(st, *it);
    it->rate = f.rate;
    it->rts_rate = f.rts_rate;
    af.ampdu_rest.push_back(std::move(*it));
    it = af.queue.erase(it);
  }
  return bytes;
}

// An A-MPDU of `current` and ampdu_rest, answered by a BlockAck (implicit BlockAckReq).
void SendAmpdu(State& s, int station, int psdu_bytes) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  const TimeNs block_ack_time_ns = s.phy.sifs_ns + BlockAckNs(*f.rate);
  TimeNs duration_ns = block_ack_time_ns;
  const TimeNs ppdu_ns = PpduDurationNs(f.rate->data.mode, f.rate->data.header, psdu_bytes);
  if (af.txop_start_ns >= 0) {
    duration_ns = std::max(RemainingTxopNs(s, af, ac) - ppdu_ns, block_ack_time_ns);
  }
  std::vector<AmpduSubframe>& subframes = st.ampdu_staging;
  subframes.clear();
  const bool retry = f.data_sent_before;
  int offset = 0;
  auto add = [&](QueuedFrame& m) {
    if (offset > 0) offset += (4 - offset % 4) % 4;
    subframes.push_back({m.ethernet, m.sequence_number, m.data_sent_before, offset});
    offset += kMpduDelimiterBytes + DataMpduBytes(s, m);
    ++st.counters.data_tx;
    if (m.data_sent_before) ++st.counters.retries;
    m.data_sent_before = true;
  };
  add(f);
  for (QueuedFrame& m : af.ampdu_rest) add(m);
  SITLNET_DEMAND(offset == psdu_bytes);
  Transmission& tx = StartTransmission(s, station, FrameKind::kData, f.rate->data, psdu_bytes,
                                       f.destination, Micros(duration_ns), &subframes);
  tx.retry = retry;
  tx.sequence_number = f.sequence_number;
  tx.tid = f.tid;
  tx.ethernet = f.ethernet;
  tx.ampdu_reference = st.next_ampdu_reference++;
  ++st.counters.ampdu_tx;
  st.exchange = Exchange::kWaitBlockAck;
}

// After a missed BlockAck: a compressed BlockAckReq from the frame in service, at the
// BlockAck's rate (ns-3 3.37's SendMpduFromBaManager: "the same TXVECTOR as the BlockAck").
void SendBlockAckReq(State& s, int station) {
  StationState& st = s.stations[station];
  AccessFunction& af = Exchanging(s, station);
  QueuedFrame& f = af.current;
  const RateEntry& bar_rate = RateFor(s, f.rate->control.mode);
  const TimeNs duration_ns = s.phy.sifs_ns + BlockAckNs(bar_rate);
  Transmission& tx = StartTransmission(s, station, FrameKind::kBlockAckReq, f.rate->control,
                                       kBlockAckReqBytes, f.destination, Micros(duration_ns));
  tx.ba_ssn = f.sequence_number;
  tx.tid = f.tid;
  ++st.counters.block_ack_req_tx;
  st.exchange = Exchange::kWaitBlockAck;
}

void SendData(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  if (f.type == MpduType::kData && !f.group &&
      EstablishedAgreement(s, station, f.destination, f.tid) != nullptr) {
    const uint32_t max_bytes = MaxAmpduBytes(s, ac, f.rate->data.mode);
    if (max_bytes > 0) {
      const int psdu_bytes = CollectAmpdu(s, station, ac, max_bytes);
      if (!af.ampdu_rest.empty()) {
        SendAmpdu(s, station, psdu_bytes);
        return;
      }
    }
  }
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
                        DataPsduBytes(s, f), f.destination, Micros(duration_ns));
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
  st.exchange = f.group ? Exchange::kIdle : Exchange::kWaitAck;
}

// ChooseRates, and the lowest basic rate for an action frame.
void ChooseFrameRates(State& s, int station) {
  ChooseRates(s, station);
  QueuedFrame& f = Exchanging(s, station).current;
  if (f.type != MpduType::kData) {
    f.rate = f.rts_rate = ManagementRate(s);
    f.use_rts = false;
  }
}

// What the access sends before the frame in service: a BlockAckReq owed after a missed
// BlockAck (true: sent), or an ADDBA Request put in service ahead of the frame (ns-3 3.37's
// HtFrameExchangeManager::StartFrameExchange). The Request's starting sequence number is the
// frame's.
bool PrepareCurrent(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  if (af.bar_pending) {
    ChooseRates(s, station);
    SendBlockAckReq(s, station);
    return true;
  }
  if (NeedSetupBlockAck(s, station, ac, af.current)) {
    QueuedFrame request;
    request.type = MpduType::kAddbaRequest;
    request.destination = af.current.destination;
    request.tid = af.current.tid;
    request.ba_ssn = af.current.sequence_number;
    request.enqueued_ns = s.now_ns;
    af.queue.push_front(std::move(af.current));
    af.current = std::move(request);
    AssignSequence(st, af.current);
  }
  return false;
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
  TimeNs duration_ns =
      3 * s.phy.sifs_ns + f.rts_rate->cts_ns + DataDurationNs(s, f) + f.rate->ack_ns;
  if (af.txop_start_ns >= 0) {
    duration_ns = RemainingTxopNs(s, af, ac) -
                  PpduDurationNs(rts_mode.mode, rts_mode.header, kRtsBytes);
    duration_ns = std::max<TimeNs>(duration_ns, 0);
  }
  StartTransmission(s, station, FrameKind::kRts, rts_mode, kRtsBytes, f.destination,
                    Micros(duration_ns));
  ++st.counters.rts_tx;
  st.exchange = Exchange::kWaitCts;
}

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
    TraceDrop(s, station, DropReason::kQueueExpired, f.destination, f.sequence_number,
              EthernetBytes(f));
  };
  // Frames are queued in arrival order, so the expired ones are a prefix.
  while (!af.queue.empty() && expired(af.queue.front())) {
    drop(af.queue.front());
    af.queue.pop_front();
  }
  if (include_current && af.has_current && expired(af.current)) {
    drop(af.current);
    af.bar_pending = false;
    NextFrame(s, station, ac);  // The contention window stays as it is, as in ns-3.
  }
}

size_t FramesHeld(const AccessFunction& f) { return f.queue.size() + (f.has_current ? 1 : 0); }

// Releases the TXOP of `ac` and draws a new backoff (ns-3's NotifyChannelReleased).
void ReleaseTxop(State& s, int station, int ac) {
  s.stations[station].acs[ac].txop_start_ns = -1;
  StartBackoff(s, station, ac);
}

// A BlockAck answers `tx` (an A-MPDU or a BlockAckReq) a SIFS later at the ACK's rate (ns-3's
// GetBlockAckTxVector: the control answer mode of the data's), its Duration the rest of tx's.
void ScheduleBlockAck(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  StationState& st = s.stations[station];
  const RateEntry& answered = RateFor(s, tx.mode->mode);
  const TimeNs rest_ns = tx.duration_us * kNsPerUs - s.phy.sifs_ns - BlockAckNs(answered);
  ScheduleResponse(s, station, FrameKind::kBlockAck, tx.ta,
                   rest_ns >= kNsPerUs ? Micros(rest_ns) : 0, &answered, entry.sinr);
  st.response_source = tx.source;
  st.response_tid = tx.tid;
}

// The addressed receiver decoded at least one MPDU of an A-MPDU: those it decoded go to the
// reordering buffer, and a BlockAck answers.
void ReceiveAmpdu(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  BaRecipient* agreement = RecipientAgreement(s, station, tx.source, tx.tid);
  if (agreement == nullptr) return;  // No agreement: ns-3 drops it; no BlockAck.
  for (size_t i = 0; i < tx.subframes.size(); ++i) {
    if (tx.subframe_outcome[i] != RxOutcome::kReceived) continue;
    const AmpduSubframe& m = tx.subframes[i];
    ReceiveUnderAgreement(s, station, *agreement, m.sequence_number, m.ethernet, entry.power_dbm,
                          entry.sinr);
  }
  ScheduleBlockAck(s, station, tx, entry);
}

// An ADDBA Request or Response addressed here: ACKed like data. A Request creates the
// recipient's agreement and queues the Response at the head of the TID's access category
// (ns-3 3.37's SendAddBaResponse; a retried Request whose Response is still queued queues none).
// A Response establishes the originator's agreement.
void ReceiveAction(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  StationState& st = s.stations[station];
  const RateEntry& answered = RateFor(s, tx.mode->mode);
  const TimeNs rest_ns = tx.duration_us * kNsPerUs - s.phy.sifs_ns - answered.ack_ns;
  ScheduleResponse(s, station, FrameKind::kAck, tx.ta, rest_ns >= kNsPerUs ? Micros(rest_ns) : 0,
                   &answered, entry.sinr);
  if (tx.addba_response) {
    OnAddbaResponse(s, station, tx.ta, tx.tid);
    return;
  }
  const int ac = AccessFunctionFor(s, tx.tid);
  AccessFunction& af = st.acs[ac];
  auto is_response = [&](const QueuedFrame& f) {
    return f.type == MpduType::kAddbaResponse && f.destination == tx.ta && f.tid == tx.tid;
  };
  if ((af.has_current && is_response(af.current)) ||
      std::any_of(af.queue.begin(), af.queue.end(), is_response)) {
    return;
  }
  CreateRecipientAgreement(s, station, tx.source, tx.tid, tx.ba_ssn);
  QueuedFrame response;
  response.type = MpduType::kAddbaResponse;
  response.destination = tx.ta;
  response.tid = tx.tid;
  response.enqueued_ns = s.now_ns;
  af.queue.push_front(std::move(response));
  if (!af.has_current) {
    NextFrame(s, station, ac);
    RequestAccess(s, station, ac);
  }
}

// The BlockAck of an A-MPDU or a BlockAckReq: what it acknowledges is done; the rest goes back
// to the head of the queue, in order, for the next A-MPDU (ns-3 3.37's
// BlockAckManager::NotifyGotBlockAck). A BlockAck resets the contention window and the retry
// count, as an ACK does.
void ReceiveBlockAck(State& s, int station, const Transmission& tx) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  int acked = 0, failed = 0;
  auto covered = [&](const QueuedFrame& m) {
    return BlockAckCovers(tx.ba_ssn, tx.ba_bitmap, m.sequence_number);
  };
  const bool current_done = covered(f);
  (current_done ? acked : failed) += 1;
  if (!af.ampdu_rest.empty()) {
    for (auto it = af.ampdu_rest.rbegin(); it != af.ampdu_rest.rend(); ++it) {
      if (covered(*it)) {
        ++acked;
      } else {
        ++failed;
        af.queue.push_front(std::move(*it));
      }
    }
    af.ampdu_rest.clear();
  } else {
    // After a BlockAckReq: the MPDUs sent before wait at the head of the queue.
    for (auto it = af.queue.begin(); it != af.queue.end();) {
      if (it->type == MpduType::kData && it->data_sent_before && it->tid == f.tid &&
          it->destination == f.destination && covered(*it)) {
        ++acked;
        it = af.queue.erase(it);
      } else {
        ++it;
      }
    }
  }
  st.counters.sent_ok += static_cast<uint64_t>(acked);
  af.bar_pending = false;
  (f.use_rts ? af.long_retry_count : af.short_retry_count) = 0;
  ReportAmpduTxStatus(s, station, tx.ta, acked, failed, f.rate, tx.reported_snr);
  ExchangeSucceeded(s, station, current_done);
}

}  // namespace

void OnEnqueue(State& s, int station, Bytes ethernet) {
  StationState& st = s.stations[station];
  const int tid = s.phy.qos ? UserPriorityOf(*ethernet) : 0;
  const int ac = AccessFunctionFor(s, tid);
  AccessFunction& af = st.acs[ac];
  if (FramesHeld(af) >= s.config.queue_limit_frames) DropExpired(s, station, ac, false);
  if (FramesHeld(af) >= s.config.queue_limit_frames) {
    ++st.counters.queue_drops;
    MacAddress destination;
    std::copy_n(ethernet->begin(), 6, destination.bytes.begin());
    TraceDrop(s, station, DropReason::kQueueFull, destination, 0, ethernet->size());
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
    // Everything expired: release the channel with a new backoff (ns-3's
    // Txop::NotifyChannelReleased -> GenerateBackoff).
    StartBackoff(s, station, ac);
    return false;
  }
  // A TXOP starts with the access (ns-3's QosTxop::NotifyChannelAccessed).
  if (s.phy.edca[ac].txop_limit_ns > 0) af.txop_start_ns = s.now_ns;
  if (PrepareCurrent(s, station, ac)) return true;
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
  if (!f.group) {
    int& count = f.use_rts ? af.long_retry_count : af.short_retry_count;
    const int limit = f.use_rts ? s.config.long_retry_limit : s.config.short_retry_limit;
    RateManager& rates = *st.rate_manager;
    rates.ReportDataFailed(f.destination, s.now_ns);
    if (!rates.NeedRetransmission(f.destination, ++count < limit, s.now_ns)) {
      count = 0;
      rates.ReportFinalDataFailed(f.destination, s.now_ns);
      ++st.counters.lost_retry_limit;
      TraceDrop(s, station, DropReason::kRetryLimit, f.destination, f.sequence_number,
                EthernetBytes(f));
      af.bar_pending = false;
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
  if (af.has_current) {
    // The next frame goes if its exchange fits in what is left (ns-3's TryAddMpdu: PPDU
    // duration <= remaining - protection - SIFS - ACK).
    if (PrepareCurrent(s, station, ac)) return;
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
                         rest_ns >= kNsPerUs ? Micros(rest_ns) : 0, &answered, entry.sinr);
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
        ScheduleResponse(s, station, FrameKind::kCts, tx.ta, Micros(std::max<TimeNs>(rest, 0)),
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
        BaRecipient* agreement = RecipientAgreement(s, station, tx.source, tx.tid);
        if (agreement != nullptr) ReceiveBlockAckReq(s, station, *agreement, tx.ba_ssn);
        ScheduleBlockAck(s, station, tx, entry);
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
    case FrameKind::kBlockAck: {
      // The recipient's scoreboard as it is now: the window's start and what is buffered
      // beyond it (everything before the start was received or given up).
      const BaRecipient* agreement = RecipientAgreement(s, station, st.response_source,
                                                        st.response_tid);
      Transmission& tx =
          StartTransmission(s, station, FrameKind::kBlockAck, st.response_rate->control,
                            kBlockAckBytes, st.response_ra, st.response_duration_us);
      tx.reported_snr = st.response_snr;
      tx.tid = st.response_tid;
      if (agreement != nullptr) {
        tx.ba_ssn = agreement->window_start;
        tx.ba_bitmap = agreement->received;
      }
      ++st.counters.block_ack_tx;
      return;
    }
    case FrameKind::kRts:
    case FrameKind::kCfEnd:
    case FrameKind::kBlockAckReq:
    case FrameKind::kAction:
      return;
  }
}

}  // namespace sitlnet::mac

// The Block Ack frame exchanges of 802.11n/ac (IEEE 802.11-2016 10.12, 10.24; ns-3 3.37's
// HtFrameExchangeManager, MpduAggregator, BlockAckManager): A-MPDU and BlockAck, BlockAckReq
// and BlockAck, ADDBA Request and Response, on both sides. The agreements' state and the
// reordering buffer are in block_ack.cc; the single-frame exchanges in frame_exchange.cc.
#include <algorithm>
#include <cmath>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

int SequenceDistance(uint16_t from, uint16_t to) { return (to - from) & 0x0fff; }

// The compressed BlockAck's airtime answering a frame at `answered`'s rate.
TimeNs BlockAckNs(const RateEntry& answered) {
  return PpduDurationNs(answered.control.mode, answered.control.header, kBlockAckBytes);
}

// A QoS Data frame for `recipient` and `tid`.
bool ForAgreement(const QueuedFrame& f, const MacAddress& recipient, int tid) {
  return f.type == MpduType::kData && !f.group && f.tid == tid && f.destination == recipient;
}

// The originator's window start (ns-3's OriginatorBlockAckAgreement::GetStartingSequence):
// the oldest sequence number given and not yet acknowledged or given up, or the next one to
// give if there is none. Frames keep their order in the queue, so this is a short scan.
uint16_t OriginatorWindowStart(State& s, int station, const MacAddress& recipient, int tid) {
  const uint16_t next = PeekSequence(s, station, recipient, tid);
  const AccessFunction& af = s.stations[station].acs[AccessFunctionFor(s, tid)];
  uint16_t start = next;
  int oldest = 0;
  auto consider = [&](const QueuedFrame& f) {
    if (!f.sequence_assigned || !ForAgreement(f, recipient, tid)) return;
    const int age = SequenceDistance(f.sequence_number, next);
    if (age > oldest) {
      oldest = age;
      start = f.sequence_number;
    }
  };
  if (af.has_current) consider(af.current);
  for (const QueuedFrame& f : af.ampdu_rest) consider(f);
  for (const QueuedFrame& f : af.queue) consider(f);
  return start;
}

// MPDUs for the agreement in flight (ns-3's NeedBarRetransmission: "at least a non-expired in
// flight MPDU"). An MPDU a BlockAck reported lost waits for retransmission but is not in flight:
// a BlockAckReq owed for a given-up MPDU then finds none.
bool HasOutstanding(const State& s, int station, const MacAddress& recipient, int tid) {
  const AccessFunction& af = s.stations[station].acs[AccessFunctionFor(s, tid)];
  auto outstanding = [&](const QueuedFrame& f) {
    return f.in_flight && ForAgreement(f, recipient, tid);
  };
  return (af.has_current && outstanding(af.current)) ||
         std::any_of(af.ampdu_rest.begin(), af.ampdu_rest.end(), outstanding) ||
         std::any_of(af.queue.begin(), af.queue.end(), outstanding);
}

bool HasQueuedData(const AccessFunction& af, const MacAddress& recipient, int tid) {
  auto ours = [&](const QueuedFrame& f) { return ForAgreement(f, recipient, tid); };
  return (af.has_current && ours(af.current)) || std::any_of(af.queue.begin(), af.queue.end(), ours);
}

// The MPDUs that join `current` in an A-MPDU (ns-3 3.37's MpduAggregator::GetNextAmpdu): same
// receiver and TID, inside the Block Ack window that starts at `current`, while the A-MPDU
// stays within `max_bytes` and its PPDU within 5484 us and what is left of the TXOP (less SIFS
// and the BlockAck). With `take` they move from the queue to ampdu_rest, numbered; without,
// the walk only measures (PlannedAmpduBytes). Once the A-MPDU is longer than
// `rts_threshold_bytes` (0: never) its protection becomes RTS/CTS and `rts_protection_ns` leaves
// the TXOP too (ns-3's QosFrameExchangeManager::TryAddMpdu, qos-frame-exchange-manager.cc:331-375).
// Returns the PSDU length; *mpdus counts the MPDUs.
int WalkAmpdu(State& s, int station, int ac, uint32_t max_bytes, bool take,
              uint32_t rts_threshold_bytes, TimeNs rts_protection_ns, int* mpdus) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  const ModeEntry& mode = f.rate->data;
  const bool in_txop = af.txop_start_ns >= 0;
  const TimeNs txop_left_ns =
      in_txop ? RemainingTxopNs(s, af, ac) - s.phy.sifs_ns - BlockAckNs(*f.rate) : 0;
  auto limit_ns = [&](int bytes) {
    if (!in_txop) return kMaxPpduDurationNs;
    const bool rts = rts_threshold_bytes > 0 && static_cast<uint32_t>(bytes) > rts_threshold_bytes;
    return std::min(kMaxPpduDurationNs, txop_left_ns - (rts ? rts_protection_ns : 0));
  };
  // Without `take` nothing is numbered: the frames that would be count on from the next number.
  const uint16_t first = f.sequence_assigned ? f.sequence_number
                                             : PeekSequence(s, station, f.destination, f.tid);
  int numbered = f.sequence_assigned ? 0 : 1;
  int bytes = AmpduBytesIfAggregated(0, DataMpduBytes(s, f));
  int count = 1 + static_cast<int>(af.ampdu_rest.size());
  for (auto it = af.queue.begin(); it != af.queue.end() && count < kMaxAmpduSubframes;) {
    if (!ForAgreement(*it, f.destination, f.tid)) {
      ++it;
      continue;
    }
    const uint16_t sequence =
        it->sequence_assigned
            ? it->sequence_number
            : static_cast<uint16_t>((PeekSequence(s, station, it->destination, it->tid) + numbered) &
                                    0x0fff);
    if (SequenceDistance(first, sequence) >= kBlockAckWindow) break;
    const int with = AmpduBytesIfAggregated(bytes, DataMpduBytes(s, *it));
    if (static_cast<uint32_t>(with) > max_bytes ||
        PpduDurationNs(mode.mode, mode.header, with) > limit_ns(with)) {
      break;
    }
    bytes = with;
    ++count;
    if (!take) {
      if (!it->sequence_assigned) ++numbered;
      ++it;
      continue;
    }
    AssignSequence(s, station, *it);
    it->rate = f.rate;
    it->rts_rate = f.rts_rate;
    af.ampdu_rest.push_back(std::move(*it));
    it = af.queue.erase(it);
  }
  *mpdus = count;
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
    m.in_flight = true;
  };
  add(f);
  for (QueuedFrame& m : af.ampdu_rest) add(m);
  SITLNET_DEMAND(offset == psdu_bytes);
  Transmission& tx = StartTransmission(s, station, FrameKind::kData, f.rate->data, psdu_bytes,
                                       f.destination, DurationFieldUs(duration_ns), &subframes);
  tx.retry = retry;
  tx.sequence_number = f.sequence_number;
  tx.tid = f.tid;
  tx.ethernet = f.ethernet;
  tx.ampdu_reference = st.next_ampdu_reference++;
  ++st.counters.ampdu_tx;
  st.exchange = Exchange::kWaitBlockAck;
  st.block_ack_recipient = f.destination;
  st.block_ack_tid = f.tid;
  st.block_ack_after_bar = false;
}

// The rate of a BlockAckReq to `recipient` (ns-3 3.37's SendMpduFromBaManager): the rate
// manager's data rate for the recipient (GetDataTxVector for the BlockAckReq's header), and
// "the same TXVECTOR as the BlockAck" that data would get: its control answer rate
// (GetBlockAckTxVector). The entry returned is that control rate's, so its control entry times
// the BlockAck answering the BlockAckReq.
const RateEntry& BlockAckReqRate(State& s, int station, const MacAddress& recipient) {
  const TxRates rates = s.stations[station].rate_manager->Choose(recipient, s.now_ns);
  return RateFor(s, rates.data->control.mode);
}

// A BlockAckReq's exchange: the BlockAckReq, SIFS, the BlockAck answering it.
TimeNs BlockAckReqExchangeNs(const State& s, const RateEntry& bar_rate) {
  return PpduDurationNs(bar_rate.data.mode, bar_rate.data.header, kBlockAckReqBytes) +
         s.phy.sifs_ns + BlockAckNs(bar_rate);
}

// A compressed BlockAckReq for `agreement` at `bar_rate` (BlockAckReqRate).
void SendBlockAckReq(State& s, int station, BaOriginator& agreement, const RateEntry& bar_rate) {
  StationState& st = s.stations[station];
  const TimeNs duration_ns = s.phy.sifs_ns + BlockAckNs(bar_rate);
  Transmission& tx =
      StartTransmission(s, station, FrameKind::kBlockAckReq, bar_rate.data, kBlockAckReqBytes,
                        agreement.recipient, DurationFieldUs(duration_ns));
  tx.ba_ssn = OriginatorWindowStart(s, station, agreement.recipient, agreement.tid);
  tx.tid = agreement.tid;
  tx.retry = agreement.bar_retry;
  // Owed no more once sent (ns-3's GetBar removes it); a missed BlockAck owes it again.
  agreement.bar_pending = false;
  ++st.counters.block_ack_req_tx;
  st.exchange = Exchange::kWaitBlockAck;
  st.block_ack_recipient = agreement.recipient;
  st.block_ack_tid = agreement.tid;
  st.block_ack_after_bar = true;
}

// A BlockAck answers `tx` (an A-MPDU or a BlockAckReq) a SIFS later at the ACK's rate (ns-3's
// GetBlockAckTxVector: the control answer mode of the data's), its Duration the rest of tx's.
void ScheduleBlockAck(State& s, int station, const Transmission& tx, const RxEntry& entry) {
  StationState& st = s.stations[station];
  const RateEntry& answered = RateFor(s, tx.mode->mode);
  const TimeNs rest_ns = tx.duration_us * kNsPerUs - s.phy.sifs_ns - BlockAckNs(answered);
  ScheduleResponse(s, station, FrameKind::kBlockAck, tx.ta,
                   rest_ns >= kNsPerUs ? DurationFieldUs(rest_ns) : 0, &answered, entry.sinr);
  st.response_source = tx.source;
  st.response_tid = tx.tid;
}

// The agreement of category `ac` whose BlockAckReq goes next (ns-3's BlockAckManager::GetBar),
// or null.
BaOriginator* BarToSend(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  for (BaOriginator& a : st.ba_originator) {
    if (!a.bar_pending || a.phase != BaOriginator::Phase::kEstablished ||
        AccessFunctionFor(s, a.tid) != ac) {
      continue;
    }
    if (a.bar_only_with_data && !HasQueuedData(st.acs[ac], a.recipient, a.tid)) continue;
    return &a;
  }
  return nullptr;
}

}  // namespace

bool HasBlockAckReqToSend(State& s, int station, int ac) {
  return !s.stations[station].ba_originator.empty() && BarToSend(s, station, ac) != nullptr;
}

bool PrepareBlockAckExchange(State& s, int station, int ac, TimeNs available_ns) {
  StationState& st = s.stations[station];
  AccessFunction& af = st.acs[ac];
  // ns-3 3.37's StartFrameExchange: a BlockAckReq of this access category's BlockAckManager
  // first (GetBar), then an ADDBA Request if the frame needs an agreement.
  if (BaOriginator* a = BarToSend(s, station, ac)) {
    const RateEntry& bar_rate = BlockAckReqRate(s, station, a->recipient);
    // Past a TXOP's initial frame the exchange must fit in what is left of it; if not, the
    // frame in service is tried instead (ns-3's "Not enough time to send the BAR frame").
    if (available_ns < 0 || BlockAckReqExchangeNs(s, bar_rate) <= available_ns) {
      SendBlockAckReq(s, station, *a, bar_rate);
      return true;
    }
  }
  if (!af.has_current) return false;
  if (NeedSetupBlockAck(s, station, ac, af.current)) {
    QueuedFrame request;
    request.type = MpduType::kAddbaRequest;
    request.destination = af.current.destination;
    request.tid = af.current.tid;
    // A frame sent before keeps its number; else the next one (ns-3's startingSeq).
    request.ba_ssn = af.current.sequence_assigned
                         ? af.current.sequence_number
                         : PeekSequence(s, station, af.current.destination, af.current.tid);
    request.enqueued_ns = s.now_ns;
    af.queue.push_front(std::move(af.current));
    af.current = std::move(request);
    AssignSequence(s, station, af.current);
  }
  return false;
}

bool TrySendAmpdu(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  QueuedFrame& f = af.current;
  if (f.type != MpduType::kData || f.group ||
      EstablishedAgreement(s, station, f.destination, f.tid) == nullptr) {
    return false;
  }
  const uint32_t max_bytes = MaxAmpduBytes(s, ac, f.rate->data.mode);
  if (max_bytes == 0) return false;
  // After the RTS/CTS (if any) the TXOP left already excludes them: no protection to leave out.
  int mpdus = 0;
  const int psdu_bytes = WalkAmpdu(s, station, ac, max_bytes, true, 0, 0, &mpdus);
  if (af.ampdu_rest.empty()) return false;
  SendAmpdu(s, station, psdu_bytes);
  return true;
}

// ns-3 3.37 builds the A-MPDU before it protects it (HtFrameExchangeManager::SendDataFrame,
// ht-frame-exchange-manager.cc:506-522), so the RTS/CTS decision sees the whole PSDU.
int PlannedAmpduBytes(State& s, int station, TimeNs rts_protection_ns) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  const QueuedFrame& f = st.acs[ac].current;
  if (f.type != MpduType::kData || f.group ||
      EstablishedAgreement(s, station, f.destination, f.tid) == nullptr) {
    return 0;
  }
  const uint32_t max_bytes = MaxAmpduBytes(s, ac, f.rate->data.mode);
  if (max_bytes == 0) return 0;
  int mpdus = 0;
  const int bytes = WalkAmpdu(s, station, ac, max_bytes, false, s.config.rts_threshold_bytes,
                              rts_protection_ns, &mpdus);
  return mpdus > 1 ? bytes : 0;
}

TimeNs AmpduAndBlockAckNs(const QueuedFrame& f, int psdu_bytes) {
  return PpduDurationNs(f.rate->data.mode, f.rate->data.header, psdu_bytes) + BlockAckNs(*f.rate);
}

void BlockAckMissed(State& s, int station) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  AccessFunction& af = st.acs[ac];
  const MacAddress recipient = st.block_ack_recipient;
  const int tid = st.block_ack_tid;
  RateManager& rates = *st.rate_manager;
  rates.ReportDataFailed(recipient, s.now_ns);
  if (!st.block_ack_after_bar) {
    ReportAmpduTxStatus(s, station, recipient, 0, 1 + static_cast<int>(af.ampdu_rest.size()),
                        af.current.rate, 0);  // An A-MPDU: its first MPDU is in service.
    // The MPDUs wait at the head of the queue, in sequence order.
    for (auto it = af.ampdu_rest.rbegin(); it != af.ampdu_rest.rend(); ++it) {
      af.queue.push_front(std::move(*it));
    }
    af.ampdu_rest.clear();
  }
  // ns-3's NeedBarRetransmission first gives up the MPDUs whose lifetime ended.
  DropExpired(s, station, ac, true);
  // ns-3 3.37 (UseExplicitBarAfterMissedBlockAck): a BlockAckReq asks what got through, again
  // and again while an MPDU sent is outstanding; no retry limit applies, the MPDUs' lifetime
  // (queue_max_delay_ns) does. With none left: the failure is final and CW resets.
  BaOriginator* agreement = EstablishedAgreement(s, station, recipient, tid);
  const bool outstanding = HasOutstanding(s, station, recipient, tid);
  if (agreement != nullptr) {
    agreement->bar_pending = true;
    agreement->bar_only_with_data = !outstanding;
    agreement->bar_retry = st.block_ack_after_bar && outstanding;
  }
  if (outstanding) {
    af.cw = std::min(2 * af.cw + 1, s.phy.edca[ac].cw_max);
  } else {
    rates.ReportFinalDataFailed(recipient, s.now_ns);
    af.cw = s.phy.edca[ac].cw_min;
  }
  StartBackoff(s, station, ac);
}

void OnMpduDiscarded(State& s, int station, const QueuedFrame& f) {
  if (f.type == MpduType::kAddbaRequest) {
    OnAddbaRequestDiscarded(s, station, f.destination, f.tid);
    return;
  }
  if (f.type != MpduType::kData || f.group || !f.data_sent_before) return;
  if (BaOriginator* a = EstablishedAgreement(s, station, f.destination, f.tid)) {
    // ns-3's BlockAckManager::NotifyDiscardedMpdu: the window moves past it and a BlockAckReq
    // tells the recipient, whose buffer would otherwise wait on the hole.
    a->bar_pending = true;
    a->bar_only_with_data = false;
    a->bar_retry = false;  // A new BlockAckReq replaces any owed (ns-3's ScheduleBar).
  }
}

size_t ExpireInFlight(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  const TimeNs max_delay = s.config.queue_max_delay_ns;
  if (st.ba_originator.empty() || max_delay <= 0 || st.exchange == Exchange::kIdle ||
      st.exchange_ac != ac) {
    return 0;
  }
  AccessFunction& af = st.acs[ac];
  auto expired = [&](const QueuedFrame& f) { return f.enqueued_ns + max_delay <= s.now_ns; };
  // They stay until the exchange ends (the recipient may have them already); what matters is
  // the BlockAckReq they owe, which then follows the BlockAck, and the room they leave: ns-3
  // takes them out of the queue at once, so they no longer count against its size.
  size_t count = 0;
  if (af.has_current && expired(af.current)) {
    OnMpduDiscarded(s, station, af.current);
    ++count;
  }
  for (const QueuedFrame& f : af.ampdu_rest) {
    if (!expired(f)) continue;
    OnMpduDiscarded(s, station, f);
    ++count;
  }
  return count;
}

void OnActionAcked(State& s, int station, const QueuedFrame& f) {
  if (f.type == MpduType::kAddbaRequest) {
    OnAddbaRequestAcked(s, station, f.destination, f.tid);
  }
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
  ScheduleResponse(s, station, FrameKind::kAck, tx.ta,
                   rest_ns >= kNsPerUs ? DurationFieldUs(rest_ns) : 0, &answered, entry.sinr);
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

void ReceiveBlockAckReqFrame(State& s, int station, const Transmission& tx,
                             const RxEntry& entry) {
  BaRecipient* agreement = RecipientAgreement(s, station, tx.source, tx.tid);
  // Without an agreement ns-3 3.37 ignores it ("There's not a valid agreement for this
  // BlockAckReq"): no BlockAck.
  if (agreement == nullptr) return;
  ReceiveBlockAckReq(s, station, *agreement, tx.ba_ssn);
  ScheduleBlockAck(s, station, tx, entry);
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
  const MacAddress recipient = st.block_ack_recipient;
  const int tid = st.block_ack_tid;
  int acked = 0, failed = 0;
  auto covered = [&](const QueuedFrame& m) {
    return BlockAckCovers(tx.ba_ssn, tx.ba_bitmap, m.sequence_number);
  };
  auto sent_for_us = [&](const QueuedFrame& m) {
    return m.data_sent_before && ForAgreement(m, recipient, tid);
  };
  // After a BlockAckReq the frame in service may belong to another agreement: it stays.
  // ns-3 3.37's NotifyGotBlockAck: the in-flight MPDUs not acknowledged failed and leave the
  // flight, to be retransmitted (HandleInFlightMpdu, TO_RETRANSMIT).
  auto lost = [&](QueuedFrame& m) {
    if (!m.in_flight) return;
    ++failed;
    m.in_flight = false;
  };
  bool current_done = false;
  if (af.has_current && sent_for_us(f)) {
    current_done = covered(f);
    if (current_done) {
      ++acked;
    } else {
      lost(f);
    }
  }
  for (auto it = af.ampdu_rest.rbegin(); it != af.ampdu_rest.rend(); ++it) {
    if (covered(*it)) {
      ++acked;
    } else {
      lost(*it);
      af.queue.push_front(std::move(*it));
    }
  }
  af.ampdu_rest.clear();
  if (st.block_ack_after_bar) {
    // The MPDUs sent before wait in the queue.
    for (auto it = af.queue.begin(); it != af.queue.end();) {
      if (sent_for_us(*it) && covered(*it)) {
        ++acked;
        it = af.queue.erase(it);
      } else {
        if (ForAgreement(*it, recipient, tid)) lost(*it);
        ++it;
      }
    }
  }
  st.counters.sent_ok += static_cast<uint64_t>(acked);
  (af.has_current && f.use_rts ? af.long_retry_count : af.short_retry_count) = 0;
  ReportAmpduTxStatus(s, station, tx.ta, acked, failed, af.has_current ? f.rate : st.rate,
                      tx.reported_snr);
  // ns-3's HandleInFlightMpdu: an MPDU to retransmit whose lifetime ended is given up now (and
  // owes a BlockAckReq).
  DropExpired(s, station, ac, !current_done);
  if (BlockAckReqFollows(s, station, current_done)) return;
  ExchangeSucceeded(s, station, current_done);
}

bool BlockAckReqFollows(State& s, int station, bool current_done) {
  StationState& st = s.stations[station];
  const int ac = st.exchange_ac;
  // ns-3 3.37's HtFrameExchangeManager::TransmissionSucceeded, after a BlockAck or an ACK: with
  // a TXOP limit of 0 a BlockAckReq owed goes a SIFS later, within the same TXOP (10.22.2.8 f).
  if (st.ba_originator.empty() || s.phy.edca[ac].txop_limit_ns != 0 ||
      BarToSend(s, station, ac) == nullptr) {
    return false;
  }
  st.exchange = Exchange::kIdle;
  st.acs[ac].cw = s.phy.edca[ac].cw_min;
  if (current_done) NextFrame(s, station, ac);
  s.scheduler.Push(s.now_ns + s.phy.sifs_ns, EventType::kBlockAckReqDue, station,
                   static_cast<uint64_t>(ac));
  return true;
}

void OnBlockAckReqDue(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  st.exchange_ac = ac;
  BaOriginator* a = BarToSend(s, station, ac);
  if (a == nullptr || st.transmitting_tx >= 0) {
    StartBackoff(s, station, ac);
    return;
  }
  SendBlockAckReq(s, station, *a, BlockAckReqRate(s, station, a->recipient));
}

void SendBlockAck(State& s, int station) {
  StationState& st = s.stations[station];
  // The recipient's scoreboard as it is now (ns-3's FillBlockAckBitmap: the SSN is WinStartR,
  // the bitmap every MPDU received from there).
  const BaRecipient* agreement =
      RecipientAgreement(s, station, st.response_source, st.response_tid);
  Transmission& tx =
      StartTransmission(s, station, FrameKind::kBlockAck, st.response_rate->control,
                        kBlockAckBytes, st.response_ra, st.response_duration_us);
  tx.reported_snr = st.response_snr;
  tx.tid = st.response_tid;
  if (agreement != nullptr) {
    tx.ba_ssn = agreement->scoreboard_start;
    tx.ba_bitmap = agreement->scoreboard;
  }
  ++st.counters.block_ack_tx;
}

}  // namespace sitlnet::mac

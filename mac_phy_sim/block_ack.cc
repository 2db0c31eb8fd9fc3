// Block Ack agreements and the recipient's reordering buffer (IEEE 802.11-2016 10.24; ns-3
// 3.37's BlockAckManager, RecipientBlockAckAgreement, HtFrameExchangeManager::NeedSetupBlockAck).
#include <algorithm>
#include <cmath>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

// ns-3 3.37's QosTxop defaults: AddBaResponseTimeout 1 ms, FailedAddBaTimeout 200 ms.
constexpr TimeNs kAddbaResponseTimeoutNs = 1 * kNsPerMs;
constexpr TimeNs kFailedAddbaTimeoutNs = 200 * kNsPerMs;

int SequenceDistance(uint16_t from, uint16_t to) { return (to - from) & 0x0fff; }

// The agreement of `station` with `recipient` for `tid` in any phase, its phase brought up to
// now (the timers of ns-3 run lazily here: nothing else looks at it in between); null if none.
BaOriginator* FindOriginator(State& s, int station, const MacAddress& recipient, int tid) {
  auto& agreements = s.stations[station].ba_originator;
  for (size_t i = 0; i < agreements.size(); ++i) {
    BaOriginator& a = agreements[i];
    if (!(a.recipient == recipient) || a.tid != tid) continue;
    if (a.phase == BaOriginator::Phase::kPending && a.response_deadline_ns >= 0 &&
        s.now_ns >= a.response_deadline_ns) {
      a.phase = BaOriginator::Phase::kNoReply;
      a.reset_ns = a.response_deadline_ns + kFailedAddbaTimeoutNs;
    }
    if (a.phase == BaOriginator::Phase::kNoReply && s.now_ns >= a.reset_ns) {
      agreements.erase(agreements.begin() + static_cast<std::ptrdiff_t>(i));
      return nullptr;
    }
    return &a;
  }
  return nullptr;
}

void Deliver(State& s, int station, const BaRecipient& a, BaRecipient::Buffered& b) {
  ++s.stations[station].counters.rx_delivered;
  if (s.deliveries != nullptr) {
    s.deliveries->push_back(Delivery{station, a.originator, *b.ethernet, s.now_ns, b.power_dbm,
                                     10 * std::log10(b.sinr)});
  }
  b.ethernet.reset();
}

// Delivers the buffered MPDUs before `new_start`, in order, and moves the window there.
void MoveWindow(State& s, int station, BaRecipient& a, uint16_t new_start) {
  const int distance = SequenceDistance(a.window_start, new_start);
  for (int k = 0; k < std::min(distance, kBlockAckWindow); ++k) {
    if ((a.received >> k) & 1) Deliver(s, station, a, a.buffer[(a.window_start + k) % 64]);
  }
  a.received = distance >= kBlockAckWindow ? 0 : a.received >> distance;
  a.window_start = new_start;
}

// Moves the scoreboard's start on by `count` (ns-3's BlockAckWindow::Advance).
void AdvanceScoreboard(BaRecipient& a, int count) {
  a.scoreboard = count >= kBlockAckWindow ? 0 : a.scoreboard >> count;
  a.scoreboard_start = static_cast<uint16_t>((a.scoreboard_start + count) & 0x0fff);
}

// Delivers the MPDUs buffered in sequence from the window's start.
void DeliverInOrder(State& s, int station, BaRecipient& a) {
  while (a.received & 1) {
    Deliver(s, station, a, a.buffer[a.window_start % 64]);
    a.received >>= 1;
    a.window_start = (a.window_start + 1) & 0x0fff;
  }
}

}  // namespace

SubframeWindowNs SubframeWindow(const std::vector<AmpduSubframe>& subframes, int i,
                                double rate_mbps, TimeNs payload_ns) {
  // 16 SERVICE bits come first; a bit lasts 1000 / rate_mbps ns.
  auto bit_ns = [&](int offset_bytes) {
    return static_cast<TimeNs>(std::llround((16.0 + 8.0 * offset_bytes) * 1000.0 / rate_mbps));
  };
  const int n = static_cast<int>(subframes.size());
  SubframeWindowNs w;
  w.begin_ns = i == 0 ? 0 : std::min(bit_ns(subframes[i].offset_bytes), payload_ns);
  w.end_ns = i + 1 == n ? payload_ns : std::min(bit_ns(subframes[i + 1].offset_bytes), payload_ns);
  return w;
}

uint32_t MaxAmpduBytes(const State& s, int ac, const PhyMode& mode) {
  if (!s.config.aggregation || mode.format == PhyFormat::kLegacy) return 0;
  const uint32_t cap = mode.format == PhyFormat::kVht ? kMaxAmpduBytesVht : kMaxAmpduBytesHt;
  return std::min(s.config.max_ampdu_bytes[ac], cap);
}

bool UsesBlockAck(const State& s) {
  return s.config.aggregation || s.config.standard == Standard::k80211ac;
}

bool NeedSetupBlockAck(State& s, int station, int ac, const QueuedFrame& f) {
  if (!IsHtOrVht(s.config.standard) || f.type != MpduType::kData || f.group) return false;
  // ns-3 3.37 sets up an agreement for every recipient of a VHT station, whatever its
  // *_MaxAmpduSize says (GetVhtSupported(), ht-frame-exchange-manager.cc:131): 802.11ac
  // stations do so with aggregation off or an access category's limit 0, then send single
  // MPDUs under it. An HT station needs the category to aggregate.
  const bool vht = s.config.standard == Standard::k80211ac;
  if (!vht && (!s.config.aggregation || s.config.max_ampdu_bytes[ac] == 0)) return false;
  if (FindOriginator(s, station, f.destination, f.tid) != nullptr) return false;
  if (vht) return true;
  // "packets > 1": the frame and at least one more queued for the same recipient and TID.
  for (const QueuedFrame& q : s.stations[station].acs[ac].queue) {
    if (q.type == MpduType::kData && q.tid == f.tid && q.destination == f.destination) return true;
  }
  return false;
}

BaOriginator* EstablishedAgreement(State& s, int station, const MacAddress& recipient, int tid) {
  BaOriginator* a = FindOriginator(s, station, recipient, tid);
  return a != nullptr && a->phase == BaOriginator::Phase::kEstablished ? a : nullptr;
}

void OnAddbaRequestSent(State& s, int station, const MacAddress& recipient, int tid) {
  BaOriginator a;
  a.recipient = recipient;
  a.tid = static_cast<uint8_t>(tid);
  s.stations[station].ba_originator.push_back(a);
}

void OnAddbaRequestAcked(State& s, int station, const MacAddress& recipient, int tid) {
  BaOriginator* a = FindOriginator(s, station, recipient, tid);
  if (a != nullptr && a->phase == BaOriginator::Phase::kPending) {
    a->response_deadline_ns = s.now_ns + kAddbaResponseTimeoutNs;
  }
}

void OnAddbaRequestDiscarded(State& s, int station, const MacAddress& recipient, int tid) {
  BaOriginator* a = FindOriginator(s, station, recipient, tid);
  if (a != nullptr && a->phase == BaOriginator::Phase::kPending) {
    a->phase = BaOriginator::Phase::kNoReply;
    a->reset_ns = s.now_ns + kFailedAddbaTimeoutNs;
  }
}

void OnAddbaResponse(State& s, int station, const MacAddress& recipient, int tid) {
  BaOriginator* a = FindOriginator(s, station, recipient, tid);
  if (a != nullptr) a->phase = BaOriginator::Phase::kEstablished;
}

BaRecipient& CreateRecipientAgreement(State& s, int station, int source, int tid,
                                      uint16_t starting_sequence) {
  BaRecipient* a = RecipientAgreement(s, station, source, tid);
  if (a == nullptr) {
    a = &s.stations[station].ba_recipient.emplace_back();
    a->originator = source;
    a->tid = static_cast<uint8_t>(tid);
  }
  // A new agreement replaces the old one: what the old buffer holds goes up first, in order,
  // as when an agreement is torn down (10.24.5; ns-3 3.37's DestroyBlockAckAgreement flushes
  // it), rather than being lost.
  MoveWindow(s, station, *a, static_cast<uint16_t>((a->window_start + kBlockAckWindow) & 0x0fff));
  a->window_start = starting_sequence;
  a->received = 0;
  a->scoreboard_start = starting_sequence;
  a->scoreboard = 0;
  return *a;
}

BaRecipient* RecipientAgreement(State& s, int station, int source, int tid) {
  for (BaRecipient& a : s.stations[station].ba_recipient) {
    if (a.originator == source && a.tid == tid) return &a;
  }
  return nullptr;
}

void ReceiveUnderAgreement(State& s, int station, BaRecipient& a, uint16_t sequence_number,
                           const Bytes& ethernet, double power_dbm, double sinr) {
  // The scoreboard first, duplicates included (ns-3's NotifyReceivedMpdu; 10.24.7.3).
  const int r = SequenceDistance(a.scoreboard_start, sequence_number);
  if (r < kBlockAckWindow) {
    a.scoreboard |= uint64_t{1} << r;
  } else if (r < 2048) {
    AdvanceScoreboard(a, r - (kBlockAckWindow - 1));
    a.scoreboard |= uint64_t{1} << (kBlockAckWindow - 1);
  }
  int d = SequenceDistance(a.window_start, sequence_number);
  if (d >= 2048) {  // Before the window: already delivered or passed over (10.24.4.2).
    ++s.stations[station].counters.rx_duplicates;
    return;
  }
  if (d >= kBlockAckWindow) {
    MoveWindow(s, station, a, static_cast<uint16_t>((sequence_number - 63) & 0x0fff));
    d = kBlockAckWindow - 1;
  }
  if ((a.received >> d) & 1) {
    ++s.stations[station].counters.rx_duplicates;
    return;
  }
  a.received |= uint64_t{1} << d;
  a.buffer[sequence_number % 64] = {ethernet, power_dbm, sinr};
  DeliverInOrder(s, station, a);
}

void ReceiveBlockAckReq(State& s, int station, BaRecipient& a, uint16_t ssn) {
  // ns-3's NotifyReceivedBar: the scoreboard starts at the SSN; past its end, afresh.
  const int r = SequenceDistance(a.scoreboard_start, ssn);
  if (r > 0 && r < kBlockAckWindow) {
    AdvanceScoreboard(a, r);
  } else if (r > 0 && r < 2048) {
    a.scoreboard_start = ssn;
    a.scoreboard = 0;
  }
  const int d = SequenceDistance(a.window_start, ssn);
  if (d > 0 && d < 2048) MoveWindow(s, station, a, ssn);
  DeliverInOrder(s, station, a);
}

bool BlockAckCovers(uint16_t ssn, uint64_t bitmap, uint16_t sequence_number) {
  const int d = SequenceDistance(ssn, sequence_number);
  if (d >= 2048) return true;  // Before the recipient's window: it has moved past it.
  return d < kBlockAckWindow && ((bitmap >> d) & 1);
}

void ReportAmpduTxStatus(State& s, int station, const MacAddress& recipient, int acked,
                         int failed, const RateEntry* rate, double block_ack_snr) {
  (void)rate;  // Minstrel-HT, when it comes, needs the rate too (rate_manager.h).
  // ns-3's ReportAmpduTxStatus: the SNR the recipient measured on the A-MPDU comes back in the
  // BlockAck (0: none came); IdealWifiManager keeps a non-zero one.
  s.stations[station].rate_manager->ReportAmpduTxStatus(recipient, acked, failed, 0,
                                                        block_ack_snr, s.now_ns);
}

}  // namespace sitlnet::mac

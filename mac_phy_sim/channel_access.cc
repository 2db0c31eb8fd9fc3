// DCF and EDCA channel access (IEEE 802.11-2016 10.3.2, 10.3.4, 10.22.2): a station's medium is
// busy while it transmits, is locked on a frame, senses energy at or above
// the CCA-ED threshold, or its NAV is set. After the medium has been idle for
// DIFS (EIFS after a failed reception) the backoff counts down one slot per
// idle slot; it freezes (keeping whole elapsed slots, as ns-3's
// ChannelAccessManager does) when the medium turns busy. A station whose
// counter reaches zero in the same instant another starts, or within the 4 us
// its CCA needs to notice the other's frame, still transmits: that is how DCF
// collisions happen.
#include <algorithm>
#include <bit>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

// Visits the access functions whose bit is set in `mask`, highest category first.
template <typename F>
void ForEachPending(unsigned mask, F&& visit) {
  while (mask != 0) {
    const int ac = std::bit_width(mask) - 1;
    mask &= ~(1u << ac);
    visit(ac);
  }
}

void SetPending(StationState& st, int ac, bool pending) {
  st.acs[ac].backoff_pending = pending;
  if (pending) {
    st.pending_mask = static_cast<uint8_t>(st.pending_mask | (1u << ac));
  } else {
    st.pending_mask = static_cast<uint8_t>(st.pending_mask & ~(1u << ac));
  }
}

TimeNs AifsNs(const State& s, int ac) {
  return s.phy.sifs_ns + s.phy.edca[ac].aifsn * s.phy.slot_ns;  // 10.22.2.4
}

void ScheduleAccess(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  const TimeNs aifs = AifsNs(s, ac);
  // EIFS - DIFS + AIFS[AC] after a failed reception (ns-3's GetEifsNoDifs + AIFS).
  const TimeNs ifs = st.use_eifs ? s.phy.eifs_ns - s.phy.aifs_ns + aifs : aifs;
  // An ACK/CTS timeout counts like a busy period: AIFS must follow its end (ns-3's
  // ChannelAccessManager::GetAccessGrantStart, the last AckTimeout/CtsTimeout end + SIFS +
  // AIFSN slots).
  const TimeNs after_timeout_ns = st.timeout_end_ns + aifs;
  f.count_origin_ns = std::max({st.idle_since_ns + ifs, f.backoff_start_ns, after_timeout_ns});
  s.SetAccessAt(station, ac, f.count_origin_ns + f.backoff_slots * s.phy.slot_ns);
}

// `sensed_ns`: when channel access learns that the medium is busy: now, or
// kPreambleDetectionNs later when only an arriving frame made it so (UpdateCca).
void OnBusy(State& s, int station, int ac, TimeNs sensed_ns) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  if (f.access_at_ns < 0) return;
  // The counter reaches zero before the medium is sensed busy: transmit anyway.
  // That is how DCF collisions happen (counters ending together, or within the
  // CCA delay of each other).
  if (f.access_at_ns <= sensed_ns) return;
  if (sensed_ns > f.count_origin_ns) {
    const int elapsed = static_cast<int>((sensed_ns - f.count_origin_ns) / s.phy.slot_ns);
    f.backoff_slots -= std::min(elapsed, f.backoff_slots);
  }
  // EDCA (QoS stations) also decrements at the slot boundary that ends AIFS (10.22.2.4): ns-3
  // 3.37's ChannelAccessManager::UpdateBackoff counts one slot more for a QosTxop once AIFS has
  // passed, so a frozen counter loses one slot more than under DCF.
  if (s.phy.qos && sensed_ns >= f.count_origin_ns && f.backoff_slots > 0) --f.backoff_slots;
  // An immediate access (no backoff, 10.3.4.2) that the medium interrupted
  // turns into a random backoff, as the standard says. ns-3 3.37 keeps the
  // zero backoff instead, so every station that queued a frame during one
  // busy period sends DIFS after it, together: for group frames (no ACK, no
  // retry) each such meeting loses all of them (docs/mac_phy_sim.md). A
  // counter that was drawn and reached zero stays zero.
  if (f.immediate_access) f.backoff_slots = DrawUniform(st, f.cw);
  f.immediate_access = false;
  s.SetAccessAt(station, ac, -1);
  f.backoff_start_ns = s.now_ns;
}

// Ends the backoff of `ac` (its access time is now).
void ClearAccess(State& s, int station, int ac) {
  AccessFunction& f = s.stations[station].acs[ac];
  s.SetAccessAt(station, ac, -1);
  SetPending(s.stations[station], ac, false);
  f.backoff_slots = 0;
  f.immediate_access = false;
}

}  // namespace

int DrawUniform(StationState& st, int max_inclusive) {
  // Lemire's multiply-shift: unbiased enough for 2^64 draws, platform independent.
  const unsigned __int128 product =
      static_cast<unsigned __int128>(st.rng()) * static_cast<uint64_t>(max_inclusive + 1);
  return static_cast<int>(product >> 64);
}

int AccessFunctionFor(const State& s, int tid) {
  return static_cast<int>(s.phy.qos ? AccessCategoryOf(tid) : AccessCategory::kBestEffort);
}

void UpdateCca(State& s, int station) {
  StationState& st = s.stations[station];
  const bool signal_busy = st.rx.tx >= 0 || (st.active_signals > 0 && st.energy_mw >= s.cca_mw);
  const bool physically_busy = st.transmitting_tx >= 0 || signal_busy;
  const bool nav_busy = st.nav_until_ns > s.now_ns;
  // The NAV needs its own expiry event only while it alone holds the medium
  // busy: physical changes call UpdateCca anyway (for a DATA frame the NAV
  // ends exactly when its ACK does).
  if (nav_busy && !physically_busy && st.nav_event_ns != st.nav_until_ns) {
    st.nav_event_ns = st.nav_until_ns;
    s.scheduler.Push(st.nav_until_ns, EventType::kNavEnd, station, 0);
  }
  const bool busy = physically_busy || nav_busy;
  if (busy == st.busy) return;
  st.busy = busy;
  if (busy) {
    // A frame reaching an idle station makes its medium busy for channel
    // access only once preamble detection has decided, 4 us in (ns-3 3.37's
    // PhyEntity): a station whose counter ends within those 4 us still
    // transmits, a collision the slot time allows for (aSlotTime includes
    // aCCATime, IEEE 802.11-2016 DCF timing relations). The decision is
    // taken now, not by an event: an access that falls inside the 4 us is
    // kept, any other is frozen.
    const bool only_a_signal = st.transmitting_tx < 0 && !nav_busy;
    const TimeNs sensed_ns = only_a_signal ? s.now_ns + kPreambleDetectionNs : s.now_ns;
    ForEachPending(st.pending_mask, [&](int ac) { OnBusy(s, station, ac, sensed_ns); });
  } else {
    st.idle_since_ns = s.now_ns;
    // An access kept inside the 4 us stands if the medium turns idle again
    // before it (a second frame broke the first's preamble detection and the
    // energy left is under CCA-ED; or a weak signal that held the energy over
    // it ended): ns-3 never saw the medium busy.
    ForEachPending(st.pending_mask, [&](int ac) {
      if (st.acs[ac].access_at_ns < 0) ScheduleAccess(s, station, ac);
    });
  }
}

void SetNav(State& s, int station, TimeNs until_ns) {
  StationState& st = s.stations[station];
  if (until_ns <= st.nav_until_ns) return;
  st.nav_until_ns = until_ns;  // UpdateCca schedules the expiry check if needed.
}

void StartBackoff(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  f.backoff_slots = DrawUniform(st, f.cw);
  f.immediate_access = false;
  f.backoff_start_ns = s.now_ns;
  SetPending(st, ac, true);
  s.SetAccessAt(station, ac, -1);
  if (!st.busy) ScheduleAccess(s, station, ac);
}

void RescheduleAccess(State& s, int station) {
  StationState& st = s.stations[station];
  if (st.busy) return;
  ForEachPending(st.pending_mask, [&](int ac) {
    if (st.acs[ac].access_at_ns >= 0) ScheduleAccess(s, station, ac);
  });
}

void RequestAccess(State& s, int station, int ac) {
  StationState& st = s.stations[station];
  AccessFunction& f = st.acs[ac];
  // Access will come: a backoff is running, or the function holds a TXOP or an exchange.
  if (f.backoff_pending || f.txop_start_ns >= 0 ||
      (st.exchange != Exchange::kIdle && st.exchange_ac == ac)) {
    return;
  }
  if (st.busy) {
    StartBackoff(s, station, ac);
    return;
  }
  // 10.3.4.2: idle medium and a zero backoff counter: transmit without a
  // random backoff, DIFS after the frame arrived (ns-3 3.37's
  // NeedBackoffUponAccess starts the backoff at now + DIFS even after a long
  // idle period), or DIFS/EIFS after the last busy period if that is later.
  f.backoff_slots = 0;
  f.immediate_access = true;
  f.backoff_start_ns = s.now_ns + AifsNs(s, ac);
  SetPending(st, ac, true);
  ScheduleAccess(s, station, ac);
}

void OnAccess(State& s, int station) {
  StationState& st = s.stations[station];
  // Every access function whose time is now, highest priority first: the first with a frame
  // transmits, the others with frames collide internally (10.22.2.11.2; ns-3 3.37's
  // ChannelAccessManager::DoGrantDcfAccess). Functions without a frame end a post-backoff.
  int due[kAccessCategoryCount];
  int due_count = 0;
  ForEachPending(st.pending_mask, [&](int ac) {
    const AccessFunction& f = st.acs[ac];
    if (f.access_at_ns >= 0 && f.access_at_ns <= s.now_ns) due[due_count++] = ac;
  });
  for (int i = 0; i < due_count; ++i) ClearAccess(s, station, due[i]);
  bool granted = false;
  for (int i = 0; i < due_count; ++i) {
    const int ac = due[i];
    // Post-backoff done, unless a BlockAckReq is owed (ns-3's QosTxop::HasFramesToTransmit).
    if (!st.acs[ac].has_current && !HasBlockAckReqToSend(s, station, ac)) continue;
    if (granted) {
      OnInternalCollision(s, station, ac);
    } else if (st.transmitting_tx >= 0 || st.exchange != Exchange::kIdle) {
      StartBackoff(s, station, ac);  // Busy sending a response at this very instant.
    } else {
      granted = StartCurrentFrame(s, station, ac);
    }
  }
}

}  // namespace sitlnet::mac

namespace sitlnet::mac {

void Medium::State::SetAccessAt(int station, int ac, TimeNs access_ns) {
  StationState& st = stations[station];
  st.acs[ac].access_at_ns = access_ns;
  // The station's earliest. Only pending functions have an access time: `ac` itself may be
  // leaving the mask (it is cleared after this call), so it is looked at in any case.
  TimeNs at_ns = access_ns;
  unsigned others = st.pending_mask & ~(1u << ac);  // None for a DCF station.
  while (others != 0) {
    const int other = std::bit_width(others) - 1;
    others &= ~(1u << other);
    const TimeNs t = st.acs[other].access_at_ns;
    if (t >= 0 && (at_ns < 0 || t < at_ns)) at_ns = t;
  }
  st.access_at_ns = at_ns;
  if (!earliest_access_valid) return;
  if (station == earliest_access_station) {
    earliest_access_valid = false;  // The minimum moved: rescan when asked.
  } else if (at_ns >= 0 && (earliest_access_station < 0 || at_ns < earliest_access_ns ||
                            (at_ns == earliest_access_ns && station < earliest_access_station))) {
    earliest_access_ns = at_ns;
    earliest_access_station = station;
  }
}

void Medium::State::EarliestAccess(TimeNs* at_ns, int* station) {
  if (!earliest_access_valid) {
    earliest_access_station = -1;
    earliest_access_ns = -1;
    for (int i = 0; i < static_cast<int>(stations.size()); ++i) {
      const TimeNs t = stations[i].access_at_ns;
      if (t >= 0 && (earliest_access_station < 0 || t < earliest_access_ns)) {
        earliest_access_ns = t;
        earliest_access_station = i;
      }
    }
    earliest_access_valid = true;
  }
  *at_ns = earliest_access_ns;
  *station = earliest_access_station;
}

}  // namespace sitlnet::mac

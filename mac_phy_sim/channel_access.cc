// DCF channel access (IEEE 802.11-2016 10.3.2, 10.3.4): a station's medium is
// busy while it transmits, is locked on a frame, senses energy at or above
// the CCA-ED threshold, or its NAV is set. After the medium has been idle for
// DIFS (EIFS after a failed reception) the backoff counts down one slot per
// idle slot; it freezes (keeping whole elapsed slots, as ns-3's
// ChannelAccessManager does) when the medium turns busy. A station whose
// counter reaches zero in the same instant another starts, or within the 4 us
// its CCA needs to notice the other's frame, still transmits: that is how DCF
// collisions happen.
#include <algorithm>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

void ScheduleAccess(State& s, int station) {
  StationState& st = s.stations[station];
  const TimeNs ifs = st.use_eifs ? s.phy.eifs_ns : s.phy.aifs_ns;
  // An expired ACK/CTS timeout counts like the end of a busy period: DIFS
  // must follow it (ns-3's ChannelAccessManager::GetAccessGrantStart, the
  // last AckTimeout/CtsTimeout end + SIFS + AIFSN slots).
  const TimeNs after_timeout_ns = st.timeout_end_ns + s.phy.aifs_ns;
  st.count_origin_ns = std::max({st.idle_since_ns + ifs, st.backoff_start_ns, after_timeout_ns});
  s.SetAccessAt(station, st.count_origin_ns + st.backoff_slots * s.phy.slot_ns);
}

// `sensed_ns`: when channel access learns that the medium is busy: now, or
// kPreambleDetectionNs later when only an arriving frame made it so (UpdateCca).
void OnBusy(State& s, int station, TimeNs sensed_ns) {
  StationState& st = s.stations[station];
  if (st.access_at_ns < 0) return;
  // The counter reaches zero before the medium is sensed busy: transmit anyway.
  // That is how DCF collisions happen (counters ending together, or within the
  // CCA delay of each other).
  if (st.access_at_ns <= sensed_ns) return;
  if (sensed_ns > st.count_origin_ns) {
    const int elapsed = static_cast<int>((sensed_ns - st.count_origin_ns) / s.phy.slot_ns);
    st.backoff_slots -= std::min(elapsed, st.backoff_slots);
  }
  // EDCA (QoS stations) also decrements at the slot boundary that ends AIFS (10.22.2.4): ns-3
  // 3.37's ChannelAccessManager::UpdateBackoff counts one slot more for a QosTxop once AIFS has
  // passed, so a frozen counter loses one slot more than under DCF.
  if (s.phy.qos && sensed_ns >= st.count_origin_ns && st.backoff_slots > 0) --st.backoff_slots;
  // An immediate access (no backoff, 10.3.4.2) that the medium interrupted
  // turns into a random backoff, as the standard says. ns-3 3.37 keeps the
  // zero backoff instead, so every station that queued a frame during one
  // busy period sends DIFS after it, together: for group frames (no ACK, no
  // retry) each such meeting loses all of them (docs/mac_phy_sim.md). A
  // counter that was drawn and reached zero stays zero.
  if (st.immediate_access) st.backoff_slots = DrawUniform(st, st.cw);
  st.immediate_access = false;
  s.SetAccessAt(station, -1);
  st.backoff_start_ns = s.now_ns;
}

}  // namespace

int DrawUniform(StationState& st, int max_inclusive) {
  // Lemire's multiply-shift: unbiased enough for 2^64 draws, platform independent.
  const unsigned __int128 product =
      static_cast<unsigned __int128>(st.rng()) * static_cast<uint64_t>(max_inclusive + 1);
  return static_cast<int>(product >> 64);
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
    OnBusy(s, station, only_a_signal ? s.now_ns + kPreambleDetectionNs : s.now_ns);
  } else {
    st.idle_since_ns = s.now_ns;
    // An access kept inside the 4 us stands if the medium turns idle again
    // before it (a second frame broke the first's preamble detection and the
    // energy left is under CCA-ED; or a weak signal that held the energy over
    // it ended): ns-3 never saw the medium busy.
    if (st.backoff_pending && st.access_at_ns < 0) ScheduleAccess(s, station);
  }
}

void SetNav(State& s, int station, TimeNs until_ns) {
  StationState& st = s.stations[station];
  if (until_ns <= st.nav_until_ns) return;
  st.nav_until_ns = until_ns;  // UpdateCca schedules the expiry check if needed.
}

void StartBackoff(State& s, int station) {
  StationState& st = s.stations[station];
  st.backoff_slots = DrawUniform(st, st.cw);
  st.immediate_access = false;
  st.backoff_start_ns = s.now_ns;
  st.backoff_pending = true;
  s.SetAccessAt(station, -1);
  if (!st.busy) ScheduleAccess(s, station);
}

void RequestAccess(State& s, int station) {
  StationState& st = s.stations[station];
  if (st.backoff_pending || st.exchange != Exchange::kIdle) return;  // Access will come.
  if (st.busy) {
    StartBackoff(s, station);
    return;
  }
  // 10.3.4.2: idle medium and a zero backoff counter: transmit without a
  // random backoff, DIFS after the frame arrived (ns-3 3.37's
  // NeedBackoffUponAccess starts the backoff at now + DIFS even after a long
  // idle period), or DIFS/EIFS after the last busy period if that is later.
  st.backoff_slots = 0;
  st.immediate_access = true;
  st.backoff_start_ns = s.now_ns + s.phy.aifs_ns;
  st.backoff_pending = true;
  ScheduleAccess(s, station);
}

void OnAccess(State& s, int station) {
  StationState& st = s.stations[station];
  s.SetAccessAt(station, -1);
  st.backoff_pending = false;
  st.backoff_slots = 0;
  st.immediate_access = false;
  if (!st.has_current || st.exchange != Exchange::kIdle) return;  // Post-backoff done.
  if (st.transmitting_tx < 0) {
    StartCurrentFrame(s, station);
  } else {
    StartBackoff(s, station);  // Busy sending a response at this very instant.
  }
}

}  // namespace sitlnet::mac

namespace sitlnet::mac {

void Medium::State::SetAccessAt(int station, TimeNs at_ns) {
  StationState& st = stations[station];
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

// DCF channel access (IEEE 802.11-2016 10.3.2, 10.3.4): a station's medium is
// busy while it transmits, is locked on a frame, senses energy at or above
// the CCA-ED threshold, or its NAV is set. After the medium has been idle for
// DIFS (EIFS after a failed reception) the backoff counts down one slot per
// idle slot; it freezes (keeping whole elapsed slots, as ns-3's
// ChannelAccessManager does) when the medium turns busy. A station whose
// counter reaches zero in the same instant another starts still transmits:
// that is how DCF collisions happen.
#include <algorithm>

#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

void ScheduleAccess(State& s, int station) {
  StationState& st = s.stations[station];
  const TimeNs ifs = st.use_eifs ? s.phy.eifs_ns : s.phy.difs_ns;
  // An expired ACK/CTS timeout counts like the end of a busy period: DIFS
  // must follow it (ns-3's ChannelAccessManager::GetAccessGrantStart, the
  // last AckTimeout/CtsTimeout end + SIFS + AIFSN slots).
  const TimeNs after_timeout_ns = st.timeout_end_ns + s.phy.difs_ns;
  st.count_origin_ns = std::max({st.idle_since_ns + ifs, st.backoff_start_ns, after_timeout_ns});
  s.SetAccessAt(station, st.count_origin_ns + st.backoff_slots * s.phy.slot_ns);
}

void OnBusy(State& s, int station) {
  StationState& st = s.stations[station];
  if (st.access_at_ns < 0) return;
  if (st.access_at_ns == s.now_ns) return;  // Counter hits zero now: transmit anyway.
  if (s.now_ns > st.count_origin_ns) {
    const int elapsed = static_cast<int>((s.now_ns - st.count_origin_ns) / s.phy.slot_ns);
    st.backoff_slots -= std::min(elapsed, st.backoff_slots);
  }
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
  if (signal_busy && st.cca_sense_from_ns < 0) {
    // A frame reaching an idle station holds its medium busy only once the
    // preamble detection has decided (ns-3 3.37 PhyEntity): a station whose
    // backoff ends within those 4 us still transmits, a collision that the
    // slot time's aCCATime allows for (IEEE 802.11-2016 10.3.7). A station
    // already busy senses it at once.
    st.cca_sense_from_ns = st.busy ? s.now_ns : s.now_ns + kPreambleDetectionNs;
    if (!st.busy) s.scheduler.Push(st.cca_sense_from_ns, EventType::kCcaSense, station, 0);
  }
  const bool physically_busy =
      st.transmitting_tx >= 0 || (signal_busy && s.now_ns >= st.cca_sense_from_ns);
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
    OnBusy(s, station);
  } else {
    st.idle_since_ns = s.now_ns;
    st.cca_sense_from_ns = -1;
    if (st.backoff_pending) ScheduleAccess(s, station);
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
  // 10.3.4.2: idle medium and a zero backoff counter: transmit once the
  // medium has been idle for DIFS/EIFS, without a random backoff.
  st.backoff_slots = 0;
  st.backoff_start_ns = s.now_ns + s.phy.difs_ns;
  st.backoff_pending = true;
  ScheduleAccess(s, station);
}

void OnAccess(State& s, int station) {
  StationState& st = s.stations[station];
  s.SetAccessAt(station, -1);
  st.backoff_pending = false;
  st.backoff_slots = 0;
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

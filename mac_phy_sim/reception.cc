// PHY reception and interference: each station sums the power of every
// signal on the air at it; the frame it is locked on accumulates its success
// probability chunk by chunk, one chunk per interval of constant interference
// (ns-3 InterferenceHelper's piecewise SINR), split into PHY header and
// payload parts that use their own modes.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/medium_state.h"

namespace sitlnet::mac {
namespace {

double ToDb(double linear) { return 10 * std::log10(linear); }

// ns-3's SimpleFrameCaptureModel: capture is possible up to CaptureWindow
// (16 us) after the preamble was detected, whatever the PHY.
constexpr TimeNs kCaptureWindowEndNs = kPreambleDetectionNs + 16 * kNsPerUs;

// Success probability of [a, b) of the locked frame at constant `sinr`.
double ChunkSuccess(const State& s, const Transmission& tx, TimeNs a, TimeNs b, double sinr) {
  double success = 1;
  const PhyHeader& header = tx.mode->header;
  const TimeNs header_end = tx.start_ns + header.preamble_and_header_ns;
  const TimeNs payload_end = tx.end_ns - header.signal_extension_ns;
  // PHY header: the SIGNAL / PLCP header bits, pro rata of the overlap.
  const TimeNs header_overlap = std::min(b, header_end) - std::max(a, tx.start_ns);
  if (header_overlap > 0 && sinr < tx.mode->header_perfect_sinr) {
    const double bits =
        header.header_bits * static_cast<double>(header_overlap) / header.preamble_and_header_ns;
    success *= ChunkSuccessRate(s.config.error_model, header.header_mode, sinr, bits);
  }
  const TimeNs payload_overlap = std::min(b, payload_end) - std::max(a, header_end);
  if (payload_overlap > 0 && sinr < tx.mode->perfect_sinr) {
    const double bits = tx.mode->mode.rate_mbps * static_cast<double>(payload_overlap) / 1000.0;
    success *= ChunkSuccessRate(s.config.error_model, tx.mode->mode, sinr, bits);
  }
  return success;
}

// An A-MPDU's chunk [a, b) at constant `sinr`: its PHY header part goes to the frame's success
// probability, each MPDU's payload part to that MPDU's (ns-3 3.37 decides each MPDU over its own
// window of the payload, PhyEntity::EndOfMpdu, after the PHY header succeeded).
void AmpduChunk(const State& s, const Transmission& tx, TimeNs a, TimeNs b, double sinr,
                Reception& rx) {
  const PhyHeader& header = tx.mode->header;
  const TimeNs header_end = tx.start_ns + header.preamble_and_header_ns;
  const TimeNs header_overlap = std::min(b, header_end) - std::max(a, tx.start_ns);
  if (header_overlap > 0 && sinr < tx.mode->header_perfect_sinr) {
    const double bits =
        header.header_bits * static_cast<double>(header_overlap) / header.preamble_and_header_ns;
    rx.success_probability *= ChunkSuccessRate(s.config.error_model, header.header_mode, sinr, bits);
  }
  if (b <= header_end || sinr >= tx.mode->perfect_sinr) return;
  const TimeNs payload_ns = tx.end_ns - header.signal_extension_ns - header_end;
  const double rate_mbps = tx.mode->mode.rate_mbps;
  const int n = static_cast<int>(tx.subframes.size());
  for (int i = 0; i < n; ++i) {
    const SubframeWindowNs w = SubframeWindow(tx.subframes, i, rate_mbps, payload_ns);
    const TimeNs overlap = std::min(b, header_end + w.end_ns) - std::max(a, header_end + w.begin_ns);
    if (overlap <= 0) continue;
    const double bits = rate_mbps * static_cast<double>(overlap) / 1000.0;
    rx.subframe_success[i] *= ChunkSuccessRate(s.config.error_model, tx.mode->mode, sinr, bits);
  }
}

// Closes the current constant-interference chunk of the locked frame at now.
void CloseChunk(State& s, StationState& st) {
  Reception& rx = st.rx;
  if (s.now_ns <= rx.chunk_start_ns) return;
  const double sinr =
      rx.power_mw / (s.transmissions[rx.tx].mode->noise_mw + rx.interference_mw);
  rx.min_sinr = std::min(rx.min_sinr, sinr);
  if (rx.success_probability > 0) {  // Already lost: later chunks cannot help.
    // In the transmitter's time frame: the signal reached this receiver delay_ns late.
    const Transmission& tx = s.transmissions[rx.tx];
    const TimeNs delay_ns = tx.rx[rx.entry].delay_ns;
    if (!tx.subframes.empty()) {
      AmpduChunk(s, tx, rx.chunk_start_ns - delay_ns, s.now_ns - delay_ns, sinr, rx);
    } else {
      rx.success_probability *=
          ChunkSuccess(s, tx, rx.chunk_start_ns - delay_ns, s.now_ns - delay_ns, sinr);
    }
  }
  rx.chunk_start_ns = s.now_ns;
}

// record_causes: the strongest signal at `st` other than transmission `except_tx`
// (source station, power); -1 if none.
int StrongestOther(const State& s, const StationState& st, int except_tx, double* power_mw) {
  int source = -1;
  *power_mw = 0;
  for (const ActiveSignal& a : st.active) {
    if (a.tx == except_tx) continue;
    const Transmission& other = s.transmissions[a.tx];
    const double mw = other.rx[a.entry].power_mw;
    if (source < 0 || mw > *power_mw) {
      source = other.source;
      *power_mw = mw;
    }
  }
  return source;
}

// ns-3's preamble thresholds (RSSI, SNR) met by the signal alone, without interference.
bool DetectableAlone(const State& s, const RxEntry& entry) {
  return entry.power_dbm >= s.config.preamble_detect_min_rssi_dbm &&
         entry.sinr >= s.preamble_snr_linear;
}

// A signal that reaches a station busy with another frame: blamed on that
// frame only if it could have been detected alone, else it was too weak anyway.
void MarkAlreadyReceiving(const State& s, RxEntry& entry, int locked_source) {
  entry.outcome = RxOutcome::kCollided;
  if (DetectableAlone(s, entry)) {
    entry.cause = RxCause::kAlreadyReceiving;
    entry.interferer = s.record_causes ? locked_source : -1;
  } else {
    entry.cause = RxCause::kBelowThreshold;
  }
}

// Marks the locked frame lost to overlapping frames.
void LoseLockedToCollision(State& s, StationState& st) {
  RxEntry& locked = s.transmissions[st.rx.tx].rx[st.rx.entry];
  locked.outcome = RxOutcome::kCollided;
  locked.cause = RxCause::kCollision;
  locked.interferer = st.rx.interferer;
}

// record_causes: a signal from `source` at `mw` overlaps the locked frame.
void NoteInterferer(State& s, StationState& st, int source, double mw) {
  if (s.record_causes && (st.rx.interferer < 0 || mw > st.rx.interferer_mw)) {
    st.rx.interferer = source;
    st.rx.interferer_mw = mw;
  }
}

void Lock(State& s, StationState& st, Transmission& tx, int entry_index, double interference_mw) {
  Reception& rx = st.rx;
  rx.tx = tx.id;
  rx.entry = entry_index;
  rx.power_mw = tx.rx[entry_index].power_mw;
  rx.start_ns = rx.chunk_start_ns = s.now_ns;
  rx.interference_mw = interference_mw;
  rx.success_probability = 1;
  if (!tx.subframes.empty()) std::fill_n(rx.subframe_success.begin(), tx.subframes.size(), 1.0);
  rx.min_sinr = std::numeric_limits<double>::infinity();
  rx.interfered = interference_mw > 0;
  rx.interferer = -1;
  rx.interferer_mw = 0;
  if (s.record_causes) rx.interferer = StrongestOther(s, st, tx.id, &rx.interferer_mw);
}

// An A-MPDU whose PHY header was `header_ok`: each MPDU succeeds on its own draw; the PPDU
// counts as decoded if any did (ns-3 reports RxOk then). The addressed receiver keeps each
// MPDU's outcome on the transmission.
bool DrawSubframes(State& s, StationState& st, Transmission& tx, bool header_ok) {
  const bool addressed = tx.ra == st.mac;
  const int n = static_cast<int>(tx.subframes.size());
  const RxOutcome lost = st.rx.interfered ? RxOutcome::kCollided : RxOutcome::kError;
  if (addressed) tx.subframe_outcome.assign(n, lost);
  if (!header_ok) return false;
  bool any = false;
  for (int i = 0; i < n; ++i) {
    const double p = st.rx.subframe_success[i];
    const bool ok = p >= 1.0 || (p > 0.0 && std::generate_canonical<double, 53>(st.rng) < p);
    any = any || ok;
    if (addressed && ok) tx.subframe_outcome[i] = RxOutcome::kReceived;
  }
  return any;
}

}  // namespace

void SignalArrives(State& s, int station, Transmission& tx, int entry_index) {
  StationState& st = s.stations[station];
  RxEntry& entry = tx.rx[entry_index];
  const double energy_before = st.active_signals > 0 ? st.energy_mw : 0.0;
  st.energy_mw = energy_before + entry.power_mw;
  ++st.active_signals;
  if (s.record_causes) st.active.push_back({tx.id, entry_index});
  entry.sinr = entry.power_mw / tx.mode->noise_mw;
  if (st.transmitting_tx >= 0) {
    entry.outcome = RxOutcome::kTransmitting;  // Half duplex.
    entry.cause = RxCause::kOwnTransmission;
    return;
  }
  if (st.rx.tx >= 0) {
    CloseChunk(s, st);
    const int locked_source = s.transmissions[st.rx.tx].source;
    if (s.now_ns < st.rx.start_ns + kPreambleDetectionNs) {
      // Still inside the preamble detection window (ns-3 PhyEntity): a
      // stronger frame takes over; either way the frame being detected must
      // keep its SINR threshold, else its preamble is missed. Two frames that
      // start together at equal power are thus both missed, as in ns-3: no
      // reception error, so no EIFS.
      Transmission& old_tx = s.transmissions[st.rx.tx];
      const bool took_over = entry.power_mw > st.rx.power_mw;
      if (took_over) {
        RxEntry& old_entry = old_tx.rx[st.rx.entry];
        old_entry.outcome = RxOutcome::kCollided;
        old_entry.cause = RxCause::kCollision;
        old_entry.interferer = s.record_causes ? tx.source : -1;
        Lock(s, st, tx, entry_index, energy_before);
      } else {
        st.rx.interference_mw += entry.power_mw;
        st.rx.interfered = true;
        NoteInterferer(s, st, tx.source, entry.power_mw);
        MarkAlreadyReceiving(s, entry, locked_source);
      }
      const double locked_noise_mw = s.transmissions[st.rx.tx].mode->noise_mw;
      if (st.rx.power_mw < s.preamble_snr_linear * (locked_noise_mw + st.rx.interference_mw)) {
        LoseLockedToCollision(s, st);
        // Neither frame is detected: the newcomer, if detectable, is lost to a collision too.
        if (!took_over && entry.cause == RxCause::kAlreadyReceiving) {
          entry.cause = RxCause::kCollision;
        }
        st.rx.tx = -1;
      }
      return;
    }
    const auto& capture = s.config.capture_margin_db;
    if (capture && s.now_ns <= st.rx.start_ns + kCaptureWindowEndNs &&
        entry.power_dbm > ToDb(st.rx.power_mw) + *capture) {
      // Frame capture (ns-3 SimpleFrameCaptureModel): drop the weaker frame.
      Transmission& old_tx = s.transmissions[st.rx.tx];
      RxEntry& old_entry = old_tx.rx[st.rx.entry];
      old_entry.outcome = RxOutcome::kCollided;
      old_entry.cause = RxCause::kCollision;
      old_entry.interferer = s.record_causes ? tx.source : -1;
      Lock(s, st, tx, entry_index, energy_before);
      return;
    }
    st.rx.interference_mw += entry.power_mw;
    st.rx.interfered = true;
    NoteInterferer(s, st, tx.source, entry.power_mw);
    MarkAlreadyReceiving(s, entry, locked_source);
    return;
  }
  // Preamble detection (ns-3 ThresholdPreambleDetectionModel): RSSI and SINR thresholds.
  const bool strong_enough = entry.power_dbm >= s.config.preamble_detect_min_rssi_dbm;
  if (strong_enough && entry.power_mw >= s.preamble_snr_linear * (tx.mode->noise_mw + energy_before)) {
    Lock(s, st, tx, entry_index, energy_before);
    return;
  }
  const bool detectable_alone = DetectableAlone(s, entry);
  entry.outcome = detectable_alone ? RxOutcome::kCollided : RxOutcome::kBelowSensitivity;
  entry.cause = detectable_alone ? RxCause::kCollision : RxCause::kBelowThreshold;
  if (detectable_alone && s.record_causes) {
    double mw;
    entry.interferer = StrongestOther(s, st, tx.id, &mw);
  }
}

bool SignalEnds(State& s, int station, Transmission& tx, int entry_index) {
  StationState& st = s.stations[station];
  RxEntry& entry = tx.rx[entry_index];
  bool decoded = false;
  if (st.rx.tx == tx.id) {
    CloseChunk(s, st);
    const double p = st.rx.success_probability;
    decoded = p >= 1.0 || (p > 0.0 && std::generate_canonical<double, 53>(st.rng) < p);
    if (!tx.subframes.empty()) decoded = DrawSubframes(s, st, tx, decoded);
    entry.sinr = st.rx.min_sinr;
    entry.outcome = decoded ? RxOutcome::kReceived
                            : (st.rx.interfered ? RxOutcome::kCollided : RxOutcome::kError);
    entry.cause = decoded ? RxCause::kDecoded
                          : (st.rx.interfered ? RxCause::kCollision : RxCause::kNoiseError);
    if (!decoded && st.rx.interfered) entry.interferer = st.rx.interferer;
    st.use_eifs = !decoded;
    st.rx.tx = -1;
  } else if (st.rx.tx >= 0) {
    CloseChunk(s, st);
    st.rx.interference_mw = std::max(0.0, st.rx.interference_mw - entry.power_mw);
  }
  if (s.record_causes) {
    for (ActiveSignal& a : st.active) {
      if (a.tx == tx.id && a.entry == entry_index) {
        a = st.active.back();
        st.active.pop_back();
        break;
      }
    }
  }
  if (--st.active_signals == 0) {
    st.energy_mw = 0;  // Exactly: no residue of floating-point subtraction.
    if (st.rx.tx >= 0) st.rx.interference_mw = 0;
  } else {
    st.energy_mw -= entry.power_mw;
    if (st.rx.tx >= 0 && st.active_signals == 1) st.rx.interference_mw = 0;
  }
  return decoded;
}

void AbortReception(State& s, int station) {
  StationState& st = s.stations[station];
  if (st.rx.tx < 0) return;
  RxEntry& locked = s.transmissions[st.rx.tx].rx[st.rx.entry];
  locked.outcome = RxOutcome::kTransmitting;
  locked.cause = RxCause::kOwnTransmission;
  st.rx.tx = -1;
}

}  // namespace sitlnet::mac

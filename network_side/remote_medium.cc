#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <span>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"

namespace sitlnet::network_side {
namespace {

namespace pm = proto::medium;

std::string MacBytes(const MacAddress& mac) {
  return std::string(mac.bytes.begin(), mac.bytes.end());
}

MacAddress MacFrom(const std::string& bytes) {
  MacAddress mac;
  if (bytes.size() == mac.bytes.size()) std::copy(bytes.begin(), bytes.end(), mac.bytes.begin());
  return mac;
}

// Index of `frame` in reply->frames, appended unless one of the last few is the same bytes: the
// receivers of one transmission get their copies one after the other and its air frame follows
// the step's deliveries, so a short look back finds the frame without hashing every one.
int SharedFrameIndex(std::span<const uint8_t> frame, pm::MediumReply* reply) {
  constexpr int kLookBack = 16;
  for (int i = reply->frames_size() - 1; i >= 0 && i >= reply->frames_size() - kLookBack; --i) {
    const std::string& known = reply->frames(i);
    if (known.size() == frame.size() && std::memcmp(known.data(), frame.data(), frame.size()) == 0)
      return i;
  }
  reply->add_frames(frame.data(), frame.size());
  return reply->frames_size() - 1;
}

void ToProto(const tapbridge::AirFrame& f, pm::MediumReply* reply) {
  pm::AirFrame* out = reply->add_air();
  const mac::TxRecord& tx = f.tx;
  out->set_start_ns(tx.start_ns);
  out->set_duration_ns(tx.end_ns - tx.start_ns);
  out->set_transmitter(tx.source);
  out->set_kind(static_cast<int32_t>(tx.kind));
  out->set_retry(tx.retry);
  out->set_failed(f.failed);
  out->set_rate_mbps(tx.rate_mbps);
  out->set_channel_mhz(f.channel_mhz);
  out->set_band_5ghz(f.band_5ghz);
  out->set_ofdm(f.ofdm);
  out->set_signal_dbm(f.signal_dbm);
  out->set_noise_dbm(f.noise_dbm);
  out->set_duration_field_us(tx.duration_us);
  out->set_sequence(tx.sequence_number);
  out->set_receiver(MacBytes(tx.receiver));
  out->set_sender(MacBytes(tx.transmitter));
  out->set_frame_index(tx.ethernet_frame ? SharedFrameIndex(*tx.ethernet_frame, reply) : -1);
  out->set_qos(tx.qos);
  out->set_tid(tx.tid);
  if (tx.ampdu_reference) out->set_ampdu_reference(*tx.ampdu_reference);
  out->set_block_ack((tx.ba_starting_sequence & 0x0fffu) | (tx.ampdu_last ? 1u << 12 : 0u) |
                     (tx.addba_response ? 1u << 13 : 0u));
  out->set_ba_bitmap(tx.ba_bitmap);
  if (tx.mcs >= 0) {
    pm::HtMode* ht = out->mutable_ht();
    ht->set_mcs(tx.mcs);
    ht->set_vht(tx.vht);
    ht->set_spatial_streams(tx.spatial_streams);
    ht->set_channel_width_mhz(tx.channel_width_mhz);
    ht->set_short_guard_interval(tx.short_guard_interval);
  }
}

// Throws (naming the peer through `describe`) on an air frame that cannot be one: the peer is
// another process and its reply is input.
// `frames`: the reply's Ethernet frames, each decoded once and shared by the air frames that
// name it (a reply cannot make one copy per air frame).
tapbridge::AirFrame FromProto(const pm::AirFrame& p, const pm::MediumReply& reply,
                              std::vector<std::shared_ptr<const std::vector<uint8_t>>>* frames,
                              const std::function<std::string()>& describe) {
  tapbridge::AirFrame f;
  mac::TxRecord& tx = f.tx;
  if (p.kind() < 0 || p.kind() > static_cast<int32_t>(mac::kLastFrameKind) ||
      p.duration_ns() < 0 || p.start_ns() > std::numeric_limits<TimeNs>::max() - p.duration_ns()) {
    throw Error(describe() + ": medium reply has an air frame of kind " + std::to_string(p.kind()) +
                " lasting " + std::to_string(p.duration_ns()) + " ns");
  }
  // Radio values become radiotap fields (whole dBm, 500 kb/s units): finite and in range.
  const auto in_range = [](double value, double low, double high) {
    return std::isfinite(value) && value >= low && value <= high;
  };
  if (!in_range(p.signal_dbm(), -200, 100) || !in_range(p.noise_dbm(), -200, 100) ||
      !in_range(p.rate_mbps(), 0, 10000)) {
    throw Error(describe() +
                ": medium reply has an air frame with signal, noise or rate out of "
                "range");
  }
  tx.start_ns = p.start_ns();
  tx.end_ns = p.start_ns() + p.duration_ns();
  tx.source = p.transmitter();
  tx.kind = static_cast<mac::FrameKind>(p.kind());
  tx.retry = p.retry();
  tx.rate_mbps = p.rate_mbps();
  tx.duration_us = static_cast<uint16_t>(p.duration_field_us());
  tx.sequence_number = static_cast<uint16_t>(p.sequence());
  tx.receiver = MacFrom(p.receiver());
  tx.transmitter = MacFrom(p.sender());
  tx.qos = p.qos();
  tx.tid = static_cast<uint8_t>(p.tid() & 0x0f);
  if (p.has_ampdu_reference()) tx.ampdu_reference = p.ampdu_reference();
  tx.ba_starting_sequence = static_cast<uint16_t>(p.block_ack() & 0x0fff);
  tx.ampdu_last = (p.block_ack() >> 12) & 1;
  tx.addba_response = (p.block_ack() >> 13) & 1;
  tx.ba_bitmap = p.ba_bitmap();
  if (p.has_ht()) {
    // Radiotap fields again: a mode mac_phy_sim can send.
    const pm::HtMode& ht = p.ht();
    const int width = ht.channel_width_mhz();
    if (ht.mcs() < 0 || ht.mcs() > (ht.vht() ? 9 : 15) || ht.spatial_streams() < 1 ||
        ht.spatial_streams() > 2 || (width != 20 && width != 40 && width != 80)) {
      throw Error(describe() + ": medium reply has an air frame with HT/VHT mcs " +
                  std::to_string(ht.mcs()) + ", " + std::to_string(ht.spatial_streams()) +
                  " stream(s), " + std::to_string(width) + " MHz");
    }
    tx.mcs = ht.mcs();
    tx.vht = ht.vht();
    tx.spatial_streams = ht.spatial_streams();
    tx.channel_width_mhz = width;
    tx.short_guard_interval = ht.short_guard_interval();
  }
  if (tx.kind == mac::FrameKind::kData) {
    const int i = p.frame_index();
    if (i < 0 || i >= reply.frames_size() || reply.frames(i).size() < 14) {
      throw Error(describe() + ": medium reply's data air frame names frame " + std::to_string(i) +
                  " of " + std::to_string(reply.frames_size()) +
                  " (an Ethernet frame of at least 14 bytes)");
    }
    frames->resize(reply.frames_size());
    if (!(*frames)[i]) {
      (*frames)[i] = std::make_shared<const std::vector<uint8_t>>(reply.frames(i).begin(),
                                                                  reply.frames(i).end());
    }
    tx.ethernet_frame = (*frames)[i];
  }
  f.failed = p.failed();
  f.channel_mhz = p.channel_mhz();
  f.band_5ghz = p.band_5ghz();
  f.ofdm = p.ofdm();
  f.signal_dbm = p.signal_dbm();
  f.noise_dbm = p.noise_dbm();
  return f;
}

}  // namespace

uint64_t MediumScenarioHash(const Scenario& scenario) {
  Scenario copy = scenario;
  copy.spec.mutable_timing()->clear_duration_ms();
  copy.spec.mutable_timing()->clear_pacing();
  copy.spec.mutable_timing()->clear_wait_for_robots();  // When the clock starts: not the medium's
  return coordinator::ScenarioHash(copy);
}

//------------------------------ Coordinator's host ---------------------------

RemoteMedium::RemoteMedium(const Scenario& scenario,
                           std::unique_ptr<coordinator::Connector> connector,
                           TimeNs answer_timeout_ns)
    : connector_(std::move(connector)),
      network_step_ns_(scenario.network_step_ns),
      answer_timeout_ns_(answer_timeout_ns),
      stations_(static_cast<int>(scenario.robots.size())),
      counters_(scenario.robots.size()) {}

// Without an explicit Stop the run is being unwound by an error.
RemoteMedium::~RemoteMedium() { Stop("the run ended early (see the coordinator's output)"); }

void RemoteMedium::Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) {
  submit_pending_ = true;
  // What the peer may deliver of it: one copy to every other station, at most, and no frame
  // longer than the longest the robots sent.
  delivery_budget_ += std::max(1, stations_ - 1);
  air_budget_ += kAirFramesPerFrameSent;
  longest_submitted_bytes_ = std::max(longest_submitted_bytes_, ethernet.size());
  pm::SubmitOp* op = NewOp()->mutable_submit();
  op->set_station(station);
  op->set_at_ns(at_ns);
  op->set_ethernet(ethernet.data(), ethernet.size());
}

void RemoteMedium::AdvanceTo(TimeNs until_ns, std::vector<mac::Delivery>* deliveries,
                             std::vector<tapbridge::AirFrame>* air) {
  pm::AdvanceOp* op = NewOp()->mutable_advance();
  op->set_until_ns(until_ns);
  op->set_trace_air(air != nullptr);
  // The bridge's lockstep step ends here: one round trip for the whole step.
  // Earlier advances (before each frame enters) only record; what they would
  // have returned comes back, in the same order, with the step's reply.
  if (until_ns % network_step_ns_ != 0 || until_ns <= last_sent_until_ns_) {
    advance_pending_ = true;
    return;
  }
  // Nothing new entered and the medium's next event is after this step: the
  // step produces nothing; its calls go with the next request.
  if (!submit_pending_ && remote_quiet_until_ns_ >= until_ns) {
    advance_pending_ = false;  // Those recorded are known to produce nothing.
    ++stats_.quiet_steps;
    return;
  }
  const TimeNs previous_until_ns = last_sent_until_ns_;
  last_sent_until_ns_ = until_ns;
  Exchange(/*want_counters=*/false);
  // The peer's reply is input (issue 17, finding 4): a delivery it cannot have made ends the
  // link, naming it, before anything of it reaches a robot.
  const auto refuse = [this](const std::string& what) {
    healthy_ = false;
    throw Error(Describe() + ": medium reply " + what);
  };
  for (const pm::Delivery& d : reply_.deliveries()) {
    if (d.station() < 0 || d.station() >= stations_) {
      refuse("delivers to station " + std::to_string(d.station()) + " of " +
             std::to_string(stations_));
    }
    if (d.time_ns() < previous_until_ns || d.time_ns() > until_ns) {
      refuse("delivers at " + std::to_string(d.time_ns()) + " ns, outside the step [" +
             std::to_string(previous_until_ns) + ", " + std::to_string(until_ns) + "] ns");
    }
    if (!std::isfinite(d.rx_power_dbm()) || !std::isfinite(d.sinr_db())) {
      refuse("delivers with a received power or SINR that is not a number");
    }
    if (--delivery_budget_ < 0) {
      refuse("delivers more frames than the robots sent could make (one per other station)");
    }
    const std::string* frame = &d.frame();
    if (frame->empty()) {
      if (d.frame_index() < 0 || d.frame_index() >= reply_.frames_size()) {
        refuse("names frame " + std::to_string(d.frame_index()) + " of " +
               std::to_string(reply_.frames_size()));
      }
      frame = &reply_.frames(d.frame_index());
    }
    if (frame->size() > longest_submitted_bytes_) {
      refuse("delivers a frame of " + std::to_string(frame->size()) +
             " bytes, longer than any the robots sent (" +
             std::to_string(longest_submitted_bytes_) + ")");
    }
    deliveries->push_back(mac::Delivery{d.station(), d.source(),
                                        std::vector<uint8_t>(frame->begin(), frame->end()),
                                        d.time_ns(), d.rx_power_dbm(), d.sinr_db()});
  }
  if (air != nullptr) {
    std::vector<std::shared_ptr<const std::vector<uint8_t>>> frames;
    for (const pm::AirFrame& frame : reply_.air()) {
      if (frame.transmitter() < 0 || frame.transmitter() >= stations_) {
        refuse("has an air frame from station " + std::to_string(frame.transmitter()) + " of " +
               std::to_string(stations_));
      }
      // A frame on the air can have begun steps before (12 ms for 1500 bytes at 1 Mb/s).
      if (frame.start_ns() < previous_until_ns - kNsPerS || frame.start_ns() > until_ns) {
        refuse("has an air frame at " + std::to_string(frame.start_ns()) + " ns, outside the step");
      }
      if (--air_budget_ < 0) {
        refuse("has more air frames than the robots' frames could make (" +
               std::to_string(kAirFramesPerFrameSent) + " each)");
      }
      if (frame.frame_index() >= 0 && frame.frame_index() < reply_.frames_size() &&
          reply_.frames(frame.frame_index()).size() > longest_submitted_bytes_) {
        refuse("has an air frame longer than any the robots sent");
      }
      try {
        air->push_back(FromProto(frame, reply_, &frames, [this] { return Describe(); }));
      } catch (const Error&) {
        healthy_ = false;
        throw;
      }
    }
  }
}

void RemoteMedium::SetPosition(int station, double x_m, double y_m, double z_m) {
  pm::PositionOp* op = NewOp()->mutable_position();
  op->set_station(station);
  op->set_x_m(x_m);
  op->set_y_m(y_m);
  op->set_z_m(z_m);
}

void RemoteMedium::SetStationEnabled(int station, bool enabled) {
  pm::EnableOp* op = NewOp()->mutable_enable();
  op->set_station(station);
  op->set_enabled(enabled);
}

tapbridge::MediumCounters RemoteMedium::Counters(int station) const {
  // Mid-step (advances recorded, not sent) the reply's deliveries would have
  // no caller to go to: keep the last counters; between steps only positions
  // are pending and go along.
  if (counters_stale_ && healthy_ && !stopped_ && !advance_pending_) {
    try {
      const_cast<RemoteMedium*>(this)->Exchange(/*want_counters=*/true);
    } catch (const Error&) {
      // The run reports the link's failure where it happened; counters stay
      // the last ones received.
    }
  }
  return counters_.at(station);
}

void RemoteMedium::Exchange(bool want_counters) {
  if (!healthy_ || stopped_) throw Error(Describe() + ": the medium link is down");
  request_.set_want_counters(want_counters);
  payload_.clear();
  request_.SerializeToString(&payload_);
  request_.Clear();
  advance_pending_ = false;
  submit_pending_ = false;
  start_.Clear();
  start_.set_iteration(exchange_);
  start_.set_start_ns(last_sent_until_ns_ - network_step_ns_);
  start_.set_end_ns(last_sent_until_ns_);
  start_.set_payload(std::move(payload_));
  coordinator::WaitLimits limits;
  limits.timeout_ns = answer_timeout_ns_;
  const TimeNs begin_ns = MonotonicNowNs();
  limits.deadline_ns = begin_ns + answer_timeout_ns_;
  try {
    connector_->Begin(start_, limits);
    connector_->Finish(exchange_, &end_, limits);
  } catch (const Error&) {
    healthy_ = false;
    throw;
  }
  stats_.round_trip_ns += MonotonicNowNs() - begin_ns;
  stats_.remote_busy_ns += end_.busy_ns();
  stats_.request_bytes += static_cast<int64_t>(start_.payload().size());
  stats_.reply_bytes += static_cast<int64_t>(end_.payload().size());
  ++stats_.round_trips;
  if (!reply_.ParseFromString(end_.payload())) {
    healthy_ = false;
    throw Error(Describe() + ": malformed medium reply to request " + std::to_string(exchange_));
  }
  ++exchange_;
  // AdvanceTo(t) runs every event at or before t: quiet through next - 1.
  // (A next event at the very start of time, which no medium sends, saturates.)
  remote_quiet_until_ns_ = reply_.idle() ? std::numeric_limits<TimeNs>::max()
                           : reply_.next_event_ns() == std::numeric_limits<TimeNs>::min()
                               ? reply_.next_event_ns()
                               : reply_.next_event_ns() - 1;
  if (want_counters) {
    if (reply_.counters_size() != stations_) {
      healthy_ = false;
      throw Error(Describe() + ": medium reply has counters of " +
                  std::to_string(reply_.counters_size()) + " stations, the scenario " +
                  std::to_string(stations_));
    }
    for (int i = 0; i < stations_; ++i)
      counters_[i] = tapbridge::MediumCountersFromProto(reply_.counters(i));
    counters_stale_ = false;
  } else {
    counters_stale_ = true;
  }
}

void RemoteMedium::Stop(const std::string& reason) {
  if (stopped_) return;
  stopped_ = true;
  connector_->Stop(reason);
}

//--------------------------------- Other host --------------------------------

MediumLinkSimulator::MediumLinkSimulator(const Scenario& scenario,
                                         std::unique_ptr<tapbridge::MediumModel> medium)
    : medium_(std::move(medium)),
      stations_(static_cast<int>(scenario.robots.size())),
      last_time_ns_(kMaxDurationMs * kNsPerMs + scenario.iteration_ns) {}

void MediumLinkSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                       IterationContext&) {
  if (!request_.ParseFromString(start.payload())) {
    throw Error("medium request " + std::to_string(start.iteration()) +
                " is not a MediumRequest (is the coordinator a `sitlnet run --remote network`?)");
  }
  reply_.Clear();
  const auto station_ok = [&](int station) {
    if (station < 0 || station >= stations_) {
      throw Error("medium request " + std::to_string(start.iteration()) + ": station " +
                  std::to_string(station) + " out of range (the scenario has " +
                  std::to_string(stations_) + " robots)");
    }
    return station;
  };
  // The model adds durations to these times; one near int64's end (a fuzzer's INT64_MAX) would
  // overflow inside it. The coordinator never sends a time past its scenario's end, and no
  // scenario runs longer than kMaxDurationMs (this side's own duration may differ: the scenario
  // hash leaves it out, so `--duration` needs to be given only to the coordinator).
  const auto time_ok = [&](TimeNs time_ns, const char* what) {
    if (time_ns < 0 || time_ns > last_time_ns_) {
      throw Error("medium request " + std::to_string(start.iteration()) + ": " + what + " " +
                  std::to_string(time_ns) + " ns outside [0, " + std::to_string(last_time_ns_) +
                  "] ns");
    }
    return time_ns;
  };
  for (const pm::MediumOp& op : request_.ops()) {
    switch (op.kind_case()) {
      case pm::MediumOp::kSubmit: {
        // One after the other, so that a request wrong in both is named by its station.
        const int station = station_ok(op.submit().station());
        const TimeNs at_ns = time_ok(op.submit().at_ns(), "submit at");
        medium_->Submit(station, at_ns,
                        std::span<const uint8_t>(
                            reinterpret_cast<const uint8_t*>(op.submit().ethernet().data()),
                            op.submit().ethernet().size()));
        break;
      }
      case pm::MediumOp::kAdvance:
        deliveries_.clear();
        air_.clear();
        medium_->AdvanceTo(time_ok(op.advance().until_ns(), "advance until"), &deliveries_,
                           op.advance().trace_air() ? &air_ : nullptr);
        for (const mac::Delivery& d : deliveries_) {
          pm::Delivery* out = reply_.add_deliveries();
          out->set_station(d.station);
          out->set_source(d.source);
          out->set_time_ns(d.delivery_ns);
          out->set_frame_index(SharedFrameIndex(d.ethernet_frame, &reply_));
          out->set_rx_power_dbm(d.rx_power_dbm);
          out->set_sinr_db(d.sinr_db);
        }
        for (const tapbridge::AirFrame& frame : air_) ToProto(frame, &reply_);
        break;
      case pm::MediumOp::kPosition:
        medium_->SetPosition(station_ok(op.position().station()), op.position().x_m(),
                             op.position().y_m(), op.position().z_m());
        break;
      case pm::MediumOp::kEnable:
        medium_->SetStationEnabled(station_ok(op.enable().station()), op.enable().enabled());
        break;
      default:
        throw Error("medium request " + std::to_string(start.iteration()) + ": empty operation");
    }
  }
  if (const std::optional<TimeNs> next = medium_->NextEventNs()) {
    reply_.set_next_event_ns(*next);
  } else {
    reply_.set_idle(true);
  }
  if (request_.want_counters()) {
    for (int i = 0; i < stations_; ++i)
      tapbridge::MediumCountersToProto(medium_->Counters(i), reply_.add_counters());
  }
  reply_.SerializeToString(end->mutable_payload());
}

}  // namespace sitlnet::network_side

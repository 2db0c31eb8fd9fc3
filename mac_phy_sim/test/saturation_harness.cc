#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac::testing {

std::vector<uint8_t> MakeEthernetFrame(const MacAddress& to, const MacAddress& from,
                                       int payload_bytes) {
  std::vector<uint8_t> frame(14 + payload_bytes, 0);
  std::copy(to.bytes.begin(), to.bytes.end(), frame.begin());
  std::copy(from.bytes.begin(), from.bytes.end(), frame.begin() + 6);
  frame[12] = 0x08;  // IPv4 ethertype; the medium does not look past it.
  frame[13] = 0x00;
  for (int i = 0; i < payload_bytes; ++i) frame[14 + i] = static_cast<uint8_t>(i);
  return frame;
}

namespace {

struct FlowRun {
  int measured_priority = -1;  // Count only frames of this user priority; -1: all.
  std::vector<Vec3d> positions_m;
  std::vector<side_by_side::Flow> flows;
  int payload_bytes = 1500;
  TimeNs offer_interval_ns = 0;
  TimeNs warmup_ns = 0, measure_ns = 0;
};

// Every flow's source queues a frame per offer interval (side_by_side_case.h:
// the traffic ns-3's packet sockets offer in the side-by-side); counts the
// payload delivered in the measurement window.
SaturationResult RunFlows(const MediumConfig& config, const FlowRun& run) {
  Medium medium(config);
  for (size_t i = 0; i < run.positions_m.size(); ++i) {
    medium.AddStation(RobotMac(static_cast<int>(i)), run.positions_m[i]);
  }
  std::vector<std::vector<uint8_t>> frames;
  std::vector<TimeNs> next_offer_ns;
  for (size_t i = 0; i < run.flows.size(); ++i) {
    const side_by_side::Flow& flow = run.flows[i];
    frames.push_back(MakeEthernetFrame(RobotMac(flow.to), RobotMac(flow.from), run.payload_bytes));
    // The IPv4 DS byte carries the flow's user priority (priority 0 keeps the frame's byte 1).
    if (flow.priority > 0) frames.back()[15] = static_cast<uint8_t>(flow.priority << 5);
    next_offer_ns.push_back(side_by_side::OfferStartNs(static_cast<int>(i)));
  }
  const TimeNs end_ns = run.warmup_ns + run.measure_ns;
  std::vector<Delivery> deliveries;
  SaturationResult result;
  uint64_t payload_bytes = 0;
  auto count = [&] {
    for (const Delivery& d : deliveries) {
      if (run.measured_priority >= 0 && UserPriorityOf(d.ethernet_frame) != run.measured_priority) {
        continue;
      }
      if (d.delivery_ns > run.warmup_ns && d.delivery_ns <= end_ns) {
        ++result.frames_delivered;
        payload_bytes += d.ethernet_frame.size() - 14;
      }
    }
    deliveries.clear();
  };
  while (true) {
    size_t flow = 0;
    for (size_t i = 1; i < next_offer_ns.size(); ++i) {
      if (next_offer_ns[i] < next_offer_ns[flow]) flow = i;
    }
    if (next_offer_ns[flow] >= end_ns) break;
    medium.AdvanceTo(next_offer_ns[flow], &deliveries);
    count();
    medium.SubmitFrame(run.flows[flow].from, frames[flow], next_offer_ns[flow]);
    next_offer_ns[flow] += run.offer_interval_ns;
  }
  medium.AdvanceTo(end_ns, &deliveries);
  count();
  result.throughput_mbps = payload_bytes * 8.0 / (run.measure_ns / 1e9) / 1e6;
  uint64_t attempts = 0, failures = 0;
  for (const side_by_side::Flow& flow : run.flows) {
    attempts += medium.counters(flow.from).data_tx;
    failures += medium.counters(flow.from).tx_failures;
  }
  result.collision_probability = attempts ? static_cast<double>(failures) / attempts : 0;
  return result;
}

FlowRun MakeFlowRun(const side_by_side::Case& c) {
  const side_by_side::Layout layout = side_by_side::MakeLayout(c);
  FlowRun run;
  for (const side_by_side::Point& p : layout.positions) run.positions_m.push_back({p.x, p.y, p.z});
  run.flows = layout.flows;
  if (side_by_side::IsEdcaCell(c)) run.measured_priority = c.measured_priority;
  run.payload_bytes = c.payload_bytes;
  run.offer_interval_ns = side_by_side::OfferIntervalNs(c);
  run.warmup_ns = static_cast<TimeNs>(c.warmup_s * 1e9);
  run.measure_ns = static_cast<TimeNs>(c.measure_s * 1e9);
  return run;
}

}  // namespace

SaturationResult RunSaturation(const SaturationSetup& setup) {
  side_by_side::Case c;
  c.rate_mbps = setup.rate_mbps;
  c.senders = setup.stations;
  c.topology = setup.topology == Topology::kSink ? side_by_side::Topology::kSink
                                                 : side_by_side::Topology::kRing;
  c.payload_bytes = setup.payload_bytes;
  MediumConfig config = ConfigForCase(c, setup.seed);
  config.short_retry_limit = setup.retry_limit;
  config.long_retry_limit = setup.retry_limit;
  FlowRun run = MakeFlowRun(c);
  run.warmup_ns = setup.warmup_ns;
  run.measure_ns = setup.measure_ns;
  return RunFlows(config, run);
}

std::vector<TxRecord> DrainTransmissions(Medium& medium) {
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  std::vector<TxRecord> out;
  for (TraceEvent& event : trace) {
    if (event.tx) out.push_back(std::move(*event.tx));
  }
  return out;
}

std::vector<TxRecord> LinkDataFrames(const MediumConfig& config, double distance_m,
                                     TimeNs interval_ns, TimeNs duration_ns) {
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {distance_m, 0, 0});
  medium.EnableTrace(true);
  for (TimeNs t = 0; t < duration_ns; t += interval_ns) {
    medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 1500), t);
  }
  medium.AdvanceTo(duration_ns, nullptr);
  std::vector<TxRecord> data;
  for (TxRecord& tx : DrainTransmissions(medium)) {
    if (tx.kind == FrameKind::kData) data.push_back(std::move(tx));
  }
  return data;
}

uint64_t RunTopUpSaturation(int n, double seconds, uint64_t seed) {
  MediumConfig config;
  config.seed = seed;
  config.short_retry_limit = config.long_retry_limit = 1000000;  // Bianchi's assumption.
  Medium medium(config);
  const int total = n == 1 ? 2 : n;
  for (int i = 0; i < total; ++i) medium.AddStation(RobotMac(i), Vec3d{0.001 * i, 0, 0});
  std::vector<std::vector<uint8_t>> frames;
  for (int i = 0; i < n; ++i) {
    frames.push_back(MakeEthernetFrame(RobotMac((i + 1) % total), RobotMac(i), 1500));
  }
  const TimeNs step_ns = 2 * kNsPerMs;
  const TimeNs end_ns = static_cast<TimeNs>(seconds * 1e9);
  std::vector<Delivery> deliveries;
  for (TimeNs t = 0; t < end_ns; t += step_ns) {
    for (int i = 0; i < n; ++i) {
      while (medium.queued_frames(i) < 16) {
        medium.SubmitFrame(i, frames[i], t);
        medium.AdvanceTo(t, nullptr);  // Enqueue now so queued_frames() sees it.
      }
    }
    deliveries.clear();
    medium.AdvanceTo(t + step_ns, &deliveries);
  }
  uint64_t transmissions = 0;
  for (int i = 0; i < total; ++i) {
    const StationCounters& c = medium.counters(i);
    transmissions += c.data_tx + c.ack_tx;
  }
  return transmissions;
}

MediumConfig ConfigForCase(const side_by_side::Case& c, uint64_t seed) {
  MediumConfig config;
  switch (c.standard) {
    case side_by_side::Standard::kA:
      config.standard = Standard::k80211a;
      break;
    case side_by_side::Standard::kB:
      config.standard = Standard::k80211b;
      break;
    case side_by_side::Standard::kG:
      config.standard = Standard::k80211g;
      break;
    case side_by_side::Standard::kN24:
      config.standard = Standard::k80211n2_4GHz;
      break;
    case side_by_side::Standard::kN5:
      config.standard = Standard::k80211n5GHz;
      break;
    case side_by_side::Standard::kAc:
      config.standard = Standard::k80211ac;
      break;
  }
  config.short_slot = c.short_slot;
  config.rate_mbps = c.rate_mbps;
  if (side_by_side::IsHtOrVht(c.standard)) {
    config.rate_mbps = MediumConfig{}.rate_mbps;  // Unused by n/ac.
    config.mcs = c.mcs;
    config.channel_width_mhz = c.channel_width_mhz;
    config.short_guard_interval = c.short_gi;
    config.aggregation = c.ampdu;
  }
  config.rts_threshold_bytes = c.rts_threshold_bytes;
  config.qos = c.qos;
  // ns-3's Yans channel always has its constant-speed delay; at 1 mm it is 0 ns here.
  config.propagation_delay = true;
  config.jakes_fading = c.jakes;
  if (c.nakagami_m > 0) {
    config.nakagami_fading = true;
    config.nakagami_m0 = config.nakagami_m1 = config.nakagami_m2 = c.nakagami_m;
  }
  config.lognormal_shadowing_sigma_db = c.lognormal_sigma_db;
  if (c.rate_control == side_by_side::RateControl::kIdeal) {
    config.rate_control = MediumConfig::RateControl::kIdeal;
  }
  if (c.rate_control == side_by_side::RateControl::kMinstrel) {
    config.rate_control = MediumConfig::RateControl::kMinstrel;
  }
  if (c.table_error_model) config.error_model = MediumConfig::ErrorModel::kTableBased;
  if (c.capture) config.capture_margin_db = 5;  // ns-3 SimpleFrameCaptureModel's default margin.
  // At the default frequency: 5150 MHz for 11a, as ns-3's side sets.
  if (c.path_loss == side_by_side::PathLoss::kTwoRayGround) {
    config.path_loss_model = MediumConfig::PathLoss::kTwoRayGround;
  } else if (side_by_side::IsV2v(c.path_loss)) {
    config.path_loss_model = side_by_side::IsV2vUrban(c.path_loss)
                                 ? MediumConfig::PathLoss::kThreeGppV2vUrban
                                 : MediumConfig::PathLoss::kThreeGppV2vHighway;
    config.v2v_shadowing = side_by_side::HasV2vShadowing(c.path_loss);
    config.v2v_update_period_ns = c.v2v_update_period_ms * kNsPerMs;
  }
  if (c.unlimited_retries) {
    config.short_retry_limit = 1000000;
    config.long_retry_limit = 1000000;
  }
  config.seed = seed;
  return config;
}

std::vector<double> LinkLossesDb(const side_by_side::Case& c, uint64_t seed) {
  Medium medium(ConfigForCase(c, seed));
  const side_by_side::Layout layout = side_by_side::MakeLayout(c);
  for (size_t i = 0; i < layout.positions.size(); ++i) {
    const side_by_side::Point& p = layout.positions[i];
    medium.AddStation(RobotMac(static_cast<int>(i)), {p.x, p.y, p.z});
  }
  const int n = medium.station_count();
  std::vector<double> losses(static_cast<size_t>(n) * n, 0.0);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) losses[static_cast<size_t>(a) * n + b] = medium.LossDb(a, b);
  }
  return losses;
}

SaturationResult RunCase(const side_by_side::Case& c, uint64_t seed) {
  return RunFlows(ConfigForCase(c, seed), MakeFlowRun(c));
}

}  // namespace sitlnet::mac::testing

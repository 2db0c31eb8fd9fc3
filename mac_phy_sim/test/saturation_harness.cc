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
  std::vector<Vec3> positions_m;
  std::vector<side_by_side::Flow> flows;
  int payload_bytes = 1500;
  TimeNs warmup_ns = 0, measure_ns = 0;
};

// Keeps every sender's queue topped up and counts payload delivered in the
// measurement window.
SaturationResult RunFlows(const MediumConfig& config, const FlowRun& run) {
  Medium medium(config);
  for (size_t i = 0; i < run.positions_m.size(); ++i) {
    medium.AddStation(RobotMac(static_cast<int>(i)), run.positions_m[i]);
  }
  std::vector<std::vector<uint8_t>> frames;
  for (const side_by_side::Flow& flow : run.flows) {
    frames.push_back(MakeEthernetFrame(RobotMac(flow.to), RobotMac(flow.from), run.payload_bytes));
  }
  // Top up every 2 ms: at most ~5 frames leave a queue in 2 ms even alone at
  // 54 Mb/s, so 16 queued frames never run out.
  const TimeNs step_ns = 2 * kNsPerMs;
  const TimeNs end_ns = run.warmup_ns + run.measure_ns;
  std::vector<Delivery> deliveries;
  SaturationResult result;
  uint64_t payload_bytes = 0;
  for (TimeNs t = 0; t < end_ns; t += step_ns) {
    for (size_t i = 0; i < run.flows.size(); ++i) {
      while (medium.queued_frames(run.flows[i].from) < 16) {
        medium.SubmitFrame(run.flows[i].from, frames[i], t);
        medium.AdvanceTo(t, nullptr);  // Enqueue now so queued_frames() sees it.
      }
    }
    deliveries.clear();
    medium.AdvanceTo(t + step_ns, &deliveries);
    for (const Delivery& d : deliveries) {
      if (d.delivery_ns > run.warmup_ns && d.delivery_ns <= end_ns) {
        ++result.frames_delivered;
        payload_bytes += d.ethernet_frame.size() - 14;
      }
    }
  }
  result.throughput_mbps = payload_bytes * 8.0 / (run.measure_ns / 1e9) / 1e6;
  uint64_t attempts = 0, failures = 0;
  for (const side_by_side::Flow& flow : run.flows) {
    attempts += medium.counters(flow.from).data_tx;
    failures += medium.counters(flow.from).tx_failures;
  }
  result.collision_probability = attempts ? static_cast<double>(failures) / attempts : 0;
  return result;
}

}  // namespace

SaturationResult RunSaturation(const SaturationSetup& setup) {
  MediumConfig config;
  config.standard = Standard::k80211a;
  config.rate_mbps = setup.rate_mbps;
  config.short_retry_limit = setup.retry_limit;
  config.long_retry_limit = setup.retry_limit;
  config.seed = setup.seed;
  side_by_side::Case c;
  c.senders = setup.stations;
  c.topology =
      setup.topology == Topology::kSink ? side_by_side::Topology::kSink : side_by_side::Topology::kRing;
  const side_by_side::Layout layout = side_by_side::MakeLayout(c);
  FlowRun run;
  for (const side_by_side::Point& p : layout.positions) run.positions_m.push_back({p.x, p.y, p.z});
  run.flows = layout.flows;
  run.payload_bytes = setup.payload_bytes;
  run.warmup_ns = setup.warmup_ns;
  run.measure_ns = setup.measure_ns;
  return RunFlows(config, run);
}

MediumConfig ConfigForCase(const side_by_side::Case& c, uint64_t seed) {
  MediumConfig config;
  config.standard = c.standard == side_by_side::Standard::kA
                        ? Standard::k80211a
                        : (c.standard == side_by_side::Standard::kB ? Standard::k80211b
                                                                    : Standard::k80211g);
  config.short_slot = c.short_slot;
  config.rate_mbps = c.rate_mbps;
  config.rts_threshold_bytes = c.rts_threshold_bytes;
  if (c.capture) config.capture_margin_db = 5;  // ns-3 SimpleFrameCaptureModel's default margin.
  if (c.unlimited_retries) {
    config.short_retry_limit = 1000000;
    config.long_retry_limit = 1000000;
  }
  config.seed = seed;
  return config;
}

SaturationResult RunCase(const side_by_side::Case& c, uint64_t seed) {
  const side_by_side::Layout layout = side_by_side::MakeLayout(c);
  FlowRun run;
  for (const side_by_side::Point& p : layout.positions) run.positions_m.push_back({p.x, p.y, p.z});
  run.flows = layout.flows;
  run.payload_bytes = c.payload_bytes;
  run.warmup_ns = static_cast<TimeNs>(c.warmup_s * 1e9);
  run.measure_ns = static_cast<TimeNs>(c.measure_s * 1e9);
  return RunFlows(ConfigForCase(c, seed), run);
}

}  // namespace sitlnet::mac::testing

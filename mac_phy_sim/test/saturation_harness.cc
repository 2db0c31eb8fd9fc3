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

SaturationResult RunSaturation(const SaturationSetup& setup) {
  MediumConfig config;
  config.standard = Standard::k80211a;
  config.rate_mbps = setup.rate_mbps;
  config.short_retry_limit = setup.retry_limit;
  config.long_retry_limit = setup.retry_limit;
  config.seed = setup.seed;
  Medium medium(config);
  const int senders = setup.stations;
  const int total = setup.topology == Topology::kSink ? senders + 1 : senders;
  // Stations 1 mm apart, as in ns-3's Bianchi validation: everyone hears
  // everyone at the reference loss.
  for (int i = 0; i < total; ++i) medium.AddStation(RobotMac(i), Vec3d{0.001 * i, 0, 0});
  std::vector<std::vector<uint8_t>> frames;
  std::vector<int> sender_ids;
  for (int i = 0; i < senders; ++i) {
    const int id = setup.topology == Topology::kSink ? i + 1 : i;
    const int to = setup.topology == Topology::kSink ? 0 : (i + 1) % senders;
    sender_ids.push_back(id);
    frames.push_back(MakeEthernetFrame(RobotMac(to), RobotMac(id), setup.payload_bytes));
  }
  // Top up every 2 ms: at most ~5 frames leave a queue in 2 ms even alone at
  // 54 Mb/s, so 16 queued frames never run out.
  const TimeNs step_ns = 2 * kNsPerMs;
  const TimeNs end_ns = setup.warmup_ns + setup.measure_ns;
  std::vector<Delivery> deliveries;
  SaturationResult result;
  uint64_t payload_bytes = 0;
  for (TimeNs t = 0; t < end_ns; t += step_ns) {
    for (int i = 0; i < senders; ++i) {
      while (medium.queued_frames(sender_ids[i]) < 16) {
        medium.SubmitFrame(sender_ids[i], frames[i], t);
        medium.AdvanceTo(t, nullptr);  // Enqueue now so queued_frames() sees it.
      }
    }
    deliveries.clear();
    medium.AdvanceTo(t + step_ns, &deliveries);
    for (const Delivery& d : deliveries) {
      if (d.delivery_ns > setup.warmup_ns && d.delivery_ns <= end_ns) {
        ++result.frames_delivered;
        payload_bytes += d.ethernet_frame.size() - 14;
      }
    }
  }
  result.throughput_mbps = payload_bytes * 8.0 / (setup.measure_ns / 1e9) / 1e6;
  uint64_t attempts = 0, failures = 0;
  for (int id : sender_ids) {
    attempts += medium.counters(id).data_tx;
    failures += medium.counters(id).tx_failures;
  }
  result.collision_probability = attempts ? static_cast<double>(failures) / attempts : 0;
  return result;
}

}  // namespace sitlnet::mac::testing

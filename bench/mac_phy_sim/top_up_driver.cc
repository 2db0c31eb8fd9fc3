#include "bench/mac_phy_sim/top_up_driver.h"

#include <chrono>
#include <ctime>
#include <vector>

#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac::bench {
namespace {

double ProcessCpuS() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}

}  // namespace

TopUpOutcome RunTopUp(const MediumConfig& config, const TopUpSetup& setup) {
  Medium medium(config);
  for (size_t i = 0; i < setup.layout.positions.size(); ++i) {
    const side_by_side::Point& p = setup.layout.positions[i];
    medium.AddStation(RobotMac(static_cast<int>(i)), {p.x, p.y, p.z});
  }
  std::vector<std::vector<uint8_t>> frames;
  for (const side_by_side::Flow& flow : setup.layout.flows) {
    frames.push_back(
        testing::MakeEthernetFrame(RobotMac(flow.to), RobotMac(flow.from), setup.payload_bytes));
  }
  const TimeNs end_ns = setup.warmup_ns + setup.measure_ns;
  std::vector<Delivery> deliveries;
  TopUpOutcome outcome;
  uint64_t payload_bytes = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuS();
  for (TimeNs t = 0; t < end_ns; t += setup.top_up_ns) {
    for (size_t f = 0; f < setup.layout.flows.size(); ++f) {
      const StationId sender = setup.layout.flows[f].from;
      while (medium.queued_frames(sender) < static_cast<size_t>(setup.queued_frames)) {
        medium.SubmitFrame(sender, frames[f], t);
        medium.AdvanceTo(t, nullptr);  // Enqueue now so queued_frames() sees it.
      }
    }
    deliveries.clear();
    medium.AdvanceTo(t + setup.top_up_ns, &deliveries);
    outcome.mpdus_delivered_all += deliveries.size();
    for (const Delivery& d : deliveries) {
      if (d.delivery_ns <= setup.warmup_ns) continue;
      ++outcome.mpdus_delivered;
      payload_bytes += d.ethernet_frame.size() - 14;
    }
  }
  outcome.cpu_s = ProcessCpuS() - cpu_start;
  outcome.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  uint64_t data_tx = 0, ampdu_tx = 0;
  for (int i = 0; i < medium.station_count(); ++i) {
    data_tx += medium.counters(i).data_tx;
    ampdu_tx += medium.counters(i).ampdu_tx;
  }
  outcome.mpdus_per_ampdu = ampdu_tx ? static_cast<double>(data_tx) / ampdu_tx : 0;
  outcome.payload_mbps = payload_bytes * 8.0 / (static_cast<double>(setup.measure_ns) / 1e9) / 1e6;
  return outcome;
}

}  // namespace sitlnet::mac::bench

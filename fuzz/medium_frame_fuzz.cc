// Frames entering the bridge: the checks BridgeCore::EnterFrame applies to a TAP read, then the
// 802.11 medium (mac_phy_sim) the frames are submitted to, run to completion with its on-air
// trace encoded as pcap records. The input is a sequence of records
//   [station: 1 byte][gap_us: 1 byte][length: 2 bytes LE][frame: length bytes]
// so the fuzzer controls who sends what, when, and how many frames overlap on the air.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/common.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace {

constexpr char kScenario[] = R"(name: "fz"
robot { name: "a" position_m { x: 0 y: 0 z: 1 } }
robot { name: "b" position_m { x: 10 y: 0 z: 1 } }
robot { name: "c" position_m { x: 60 y: 0 z: 1 } }
radio { standard: STANDARD_80211A rate_mbps: 54 }
)";

const sitlnet::Scenario& FuzzScenario() {
  static const sitlnet::Scenario scenario = sitlnet::LoadScenarioText(kScenario, "fuzz");
  return scenario;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const sitlnet::Scenario& scenario = FuzzScenario();
  auto medium = sitlnet::tapbridge::MakeMacPhySimMedium(scenario);
  const int stations = static_cast<int>(scenario.robots.size());
  std::vector<sitlnet::tapbridge::Delivery> deliveries;
  std::vector<sitlnet::tapbridge::AirFrame> air;
  sitlnet::TimeNs now_ns = 0;
  size_t at = 0;
  std::vector<uint8_t> frame;
  while (size - at >= 4) {
    const int station = data[at] % stations;
    now_ns += static_cast<sitlnet::TimeNs>(data[at + 1]) * 1000;
    const size_t length = std::min<size_t>(data[at + 2] | (data[at + 3] << 8), size - at - 4);
    frame.assign(data + at + 4, data + at + 4 + length);
    at += 4 + length;
    // BridgeCore::EnterFrame: runts, oversize and foreign source MACs never reach the medium.
    if (frame.size() < 14 || frame.size() > medium->MaxEthernetFrameBytes()) continue;
    const auto& own = scenario.robots[station].wlan_mac.bytes;
    std::copy(own.begin(), own.end(), frame.begin() + 6);
    medium->AdvanceTo(now_ns, &deliveries, &air);
    medium->Submit(station, now_ns, frame);
  }
  // Drain: bounded, every frame is sent or dropped after its retries.
  for (int i = 0; i < 10000; ++i) {
    const auto next = medium->NextEventNs();
    if (!next) break;
    medium->AdvanceTo(*next, &deliveries, &air);
  }
  if (medium->NextEventNs()) __builtin_trap();  // The medium must go idle.
  for (const auto& air_frame : air) sitlnet::tapbridge::EncodePcapRecord(air_frame, 0);
  // Counters stay consistent. Idle medium: every frame a station sent was sent (acknowledged,
  // or a group frame on the air), lost after its retries, or dropped at a full queue.
  uint64_t sent = 0, delivered = 0;
  for (int s = 0; s < stations; ++s) {
    const auto counters = medium->Counters(s);
    sent += counters.sent;
    delivered += counters.delivered;
    uint64_t accounted = counters.queue_drops;
    for (const auto& [name, count] : counters.other) accounted += name == "sent_ok" ? count : 0;
    for (const auto& [name, count] : counters.lost) accounted += name == "retry_limit" ? count : 0;
    if (accounted != counters.sent) __builtin_trap();
  }
  if (delivered > sent * static_cast<uint64_t>(stations - 1)) __builtin_trap();
  return 0;
}

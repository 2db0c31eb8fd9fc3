// Fakes shared by the fleet tests: in-memory robot ports, a medium that logs the bridge's calls,
// random traffic, and what a bridge did, to compare a bridge over RemotePorts with one over
// local ports.
#ifndef SITLNET_FLEET_TEST_BRIDGE_FAKES_H_
#define SITLNET_FLEET_TEST_BRIDGE_FAKES_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fleet/fleet.h"

namespace sitlnet::fleet::test_support {

using Frame = std::vector<uint8_t>;

// FNV-1a: a short fingerprint of a frame, so that the call logs compare contents.
inline uint64_t Fingerprint(std::span<const uint8_t> bytes) {
  uint64_t hash = 14695981039346656037ull;
  for (const uint8_t b : bytes) hash = (hash ^ b) * 1099511628211ull;
  return hash;
}

inline std::string Describe(std::span<const uint8_t> frame) {
  return std::to_string(frame.size()) + " B #" + std::to_string(Fingerprint(frame));
}

// The 802.11 model, with a line for each call the bridge makes on it.
class RecordingMedium : public tapbridge::MediumModel {
 public:
  RecordingMedium(const Scenario& scenario, std::vector<std::string>* calls)
      : inner_(tapbridge::MakeMacPhySimMedium(scenario)), calls_(calls) {}
  void Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) override {
    calls_->push_back("submit " + std::to_string(station) + " at " + std::to_string(at_ns) + ": " +
                      Describe(ethernet));
    inner_->Submit(station, at_ns, ethernet);
  }
  void AdvanceTo(TimeNs until_ns, std::vector<tapbridge::Delivery>* deliveries,
                 std::vector<tapbridge::AirFrame>* air) override {
    calls_->push_back("advance to " + std::to_string(until_ns));
    inner_->AdvanceTo(until_ns, deliveries, air);
  }
  std::optional<TimeNs> NextEventNs() const override { return inner_->NextEventNs(); }
  void SetPosition(int station, double x_m, double y_m, double z_m) override {
    calls_->push_back("position " + std::to_string(station) + " " + std::to_string(x_m));
    inner_->SetPosition(station, x_m, y_m, z_m);
  }
  void SetStationEnabled(int station, bool enabled) override {
    calls_->push_back("enable " + std::to_string(station) + " " + std::to_string(enabled));
    inner_->SetStationEnabled(station, enabled);
  }
  tapbridge::MediumCounters Counters(int station) const override {
    return inner_->Counters(station);
  }
  size_t MaxEthernetFrameBytes() const override { return inner_->MaxEthernetFrameBytes(); }

 private:
  std::unique_ptr<tapbridge::MediumModel> inner_;
  std::vector<std::string>* calls_;
};

// A robot's TAP as a queue: what the robot sent, not read yet, and what was written to it.
struct MemoryTap {
  std::deque<Frame> sent;
  int read_errno = 0;  // Reads fail with it once `sent` is empty.
  std::vector<Frame> written;
};

// A port on this host over a MemoryTap.
class MemoryPort : public tapbridge::Port {
 public:
  explicit MemoryPort(MemoryTap* tap) : tap_(tap) {}
  ssize_t Read(std::span<uint8_t> buffer) override {
    if (tap_->sent.empty()) return -tap_->read_errno;
    const Frame frame = std::move(tap_->sent.front());
    tap_->sent.pop_front();
    const size_t length = std::min(frame.size(), buffer.size());
    std::copy_n(frame.begin(), length, buffer.begin());
    return static_cast<ssize_t>(length);
  }
  int Write(std::span<const uint8_t> frame) override {
    tap_->written.emplace_back(frame.begin(), frame.end());
    return 0;
  }
  std::optional<uint64_t> KernelTxDropped() override { return std::nullopt; }

 private:
  MemoryTap* tap_;
};

inline constexpr int kRobots = 8;

inline Scenario EightRobots(int seed = 5) {
  std::string text =
      "name: \"fleet\"\ntiming { pacing: PACING_LOCKSTEP seed: " + std::to_string(seed) + " }\n";
  for (int i = 0; i < kRobots; ++i) {
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(15 * (i % 4)) +
            " y: " + std::to_string(15 * (i / 4)) + " z: 1 } }\n";
  }
  return LoadScenarioText(text, "remote_ports_test");
}

// Frames robot `robot` sends in one step: mostly unicast and broadcast, some runts, oversize
// frames and foreign source MACs, which the bridge counts; `burst` more unicasts on top.
inline std::vector<Frame> RobotTraffic(const Scenario& scenario, int robot, std::mt19937_64* rng,
                                       int burst) {
  std::vector<Frame> frames;
  const int count = static_cast<int>((*rng)() % 3) + burst;
  for (int k = 0; k < count; ++k) {
    const int kind = k < burst ? 10 : static_cast<int>((*rng)() % 20);
    if (kind == 0) {  // Runt: shorter than an Ethernet header.
      frames.push_back(Frame(1 + (*rng)() % 13, 0x11));
      continue;
    }
    const size_t payload_bytes = kind == 1 ? 2400 : (*rng)() % 1400;  // 1: oversize.
    Frame frame(14 + payload_bytes);
    const MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
    const int other = static_cast<int>((robot + 1 + (*rng)() % (kRobots - 1)) % kRobots);
    const MacAddress destination = kind < 8 ? broadcast : scenario.robots[other].wlan_mac;
    const MacAddress source = kind == 2 ? RobotMac(99) : scenario.robots[robot].wlan_mac;
    std::copy(destination.bytes.begin(), destination.bytes.end(), frame.begin());
    std::copy(source.bytes.begin(), source.bytes.end(), frame.begin() + 6);
    frame[12] = 0x08;
    for (size_t i = 14; i < frame.size(); ++i) frame[i] = static_cast<uint8_t>((*rng)());
    frames.push_back(std::move(frame));
  }
  return frames;
}

// One bridge's view of the run: every medium call, air frame and delivery, in order.
struct BridgeLog {
  std::vector<std::string> calls;
  std::vector<std::string> air;
  std::vector<std::string> deliveries;
};

inline void Observe(tapbridge::BridgeCore* core, BridgeLog* log) {
  core->AddAirFrameObserver([log](const tapbridge::AirFrame& frame) {
    log->air.push_back(std::to_string(frame.tx.source) + " " + std::to_string(frame.tx.start_ns) +
                       "-" + std::to_string(frame.tx.end_ns) + " kind " +
                       std::to_string(static_cast<int>(frame.tx.kind)) + " failed " +
                       std::to_string(frame.failed));
  });
  core->AddDeliveryObserver([log](const tapbridge::Delivery& d) {
    log->deliveries.push_back(std::to_string(d.source) + " -> " + std::to_string(d.station) +
                              " at " + std::to_string(d.delivery_ns) + ": " +
                              Describe(d.ethernet_frame));
  });
}

// The first line where two logs part, or their lengths.
inline void ExpectSameLines(const std::vector<std::string>& local,
                            const std::vector<std::string>& remote, const std::string& what) {
  for (size_t i = 0; i < std::min(local.size(), remote.size()); ++i) {
    if (local[i] != remote[i]) {
      ADD_FAILURE() << what << " part at line " << i << ": local \"" << local[i] << "\", remote \""
                    << remote[i] << "\"";
      return;
    }
  }
  EXPECT_EQ(local.size(), remote.size()) << what;
}

}  // namespace sitlnet::fleet::test_support

#endif  // SITLNET_FLEET_TEST_BRIDGE_FAKES_H_

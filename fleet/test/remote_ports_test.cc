// A bridge over RemotePorts, fed as two node hosts would feed it, makes the same medium calls,
// air frames, deliveries and writes as a bridge whose robots' ports are on its own host (the
// identity that issue 35's byte-identical runs rest on).
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <deque>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fleet/fleet.h"
#include "fleet/node_frames_bounds.h"

namespace sitlnet::fleet {
namespace {

using Frame = std::vector<uint8_t>;

// FNV-1a: a short fingerprint of a frame, so that the call logs compare contents.
uint64_t Fingerprint(std::span<const uint8_t> bytes) {
  uint64_t hash = 14695981039346656037ull;
  for (const uint8_t b : bytes) hash = (hash ^ b) * 1099511628211ull;
  return hash;
}

std::string Describe(std::span<const uint8_t> frame) {
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

// What a node host does with its robots' TAPs: drain each one turn's budget (cutting frames
// longer than the link carries) and write what comes down.
struct FakeNode {
  NodeSlice slice;
  std::map<int, MemoryTap> taps;

  proto::node::NodeFrames Drain() {
    proto::node::NodeFrames up;
    for (const int robot : slice.robots) {
      MemoryTap& tap = taps[robot];
      proto::node::FrameBatch* batch = up.add_batches();
      batch->set_robot(robot);
      while (!tap.sent.empty() &&
             batch->frames_size() < static_cast<int>(tapbridge::kMaxFramesPerRobotPerTurn)) {
        const Frame& frame = tap.sent.front();
        batch->add_frames(frame.data(), std::min(frame.size(), kMaxNodeFrameBytes));
        tap.sent.pop_front();
      }
      if (tap.sent.empty()) batch->set_read_errno(tap.read_errno);
    }
    return up;
  }

  // Returns how many writes there were and how many frames crossed.
  std::pair<int, int> Write(const proto::node::NodeWrites& down) {
    for (const proto::node::NodeWrites::Write& write : down.writes()) {
      const std::string& frame = down.frames(write.frame_index());
      taps[write.robot()].written.emplace_back(frame.begin(), frame.end());
    }
    return {down.writes_size(), down.frames_size()};
  }
};

constexpr int kRobots = 8;

Scenario EightRobots() {
  std::string text = "name: \"fleet\"\ntiming { pacing: PACING_LOCKSTEP seed: 5 }\n";
  for (int i = 0; i < kRobots; ++i) {
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(15 * (i % 4)) +
            " y: " + std::to_string(15 * (i / 4)) + " z: 1 } }\n";
  }
  return LoadScenarioText(text, "remote_ports_test");
}

// Frames robot `robot` sends in one step: mostly unicast and broadcast, some runts, oversize
// frames and foreign source MACs, which the bridge counts; `burst` more unicasts on top.
std::vector<Frame> RobotTraffic(const Scenario& scenario, int robot, std::mt19937_64* rng,
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

void Observe(tapbridge::BridgeCore* core, BridgeLog* log) {
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
void ExpectSameLines(const std::vector<std::string>& local, const std::vector<std::string>& remote,
                     const std::string& what) {
  for (size_t i = 0; i < std::min(local.size(), remote.size()); ++i) {
    if (local[i] != remote[i]) {
      ADD_FAILURE() << what << " part at line " << i << ": local \"" << local[i] << "\", remote \""
                    << remote[i] << "\"";
      return;
    }
  }
  EXPECT_EQ(local.size(), remote.size()) << what;
}

TEST(RemotePorts, ABridgeOverTwoNodesDoesWhatItDoesOverLocalPorts) {
  const Scenario scenario = EightRobots();
  // Interleaved slices: the bridge's robot order is not the nodes' order.
  std::vector<FakeNode> nodes(2);
  nodes[0].slice = {"n0", {0, 3, 5, 6}};
  nodes[1].slice = {"n1", {1, 2, 4, 7}};
  const auto node_tap = [&nodes](int robot) -> MemoryTap& {
    FakeNode& node = std::ranges::count(nodes[0].slice.robots, robot) ? nodes[0] : nodes[1];
    return node.taps[robot];
  };

  BridgeLog local_log;
  std::vector<MemoryTap> local_taps(kRobots);
  tapbridge::BridgeOptions local_options;
  local_options.seed = 9;
  local_options.open_port = [&local_taps](int robot) {
    return std::make_unique<MemoryPort>(&local_taps[robot]);
  };
  tapbridge::BridgeCore local(
      scenario, std::make_unique<RecordingMedium>(scenario, &local_log.calls), local_options);

  BridgeLog remote_log;
  RemotePorts ports(scenario, {nodes[0].slice, nodes[1].slice});
  tapbridge::BridgeOptions remote_options;
  remote_options.seed = 9;
  remote_options.open_port = [&ports](int robot) { return ports.Open(robot); };
  tapbridge::BridgeCore remote(
      scenario, std::make_unique<RecordingMedium>(scenario, &remote_log.calls), remote_options);

  Observe(&local, &local_log);
  Observe(&remote, &remote_log);
  local.AttachAll();
  remote.AttachAll();

  std::vector<std::mt19937_64> robot_rngs;
  for (int robot = 0; robot < kRobots; ++robot) robot_rngs.emplace_back(1000 + robot);
  int writes_down = 0;
  int frames_down = 0;
  constexpr int kSteps = 40;
  constexpr int kBurstStep = 7, kBurstRobot = 3, kBurstFrames = 300;  // Over one turn's budget.
  constexpr int kFailStep = 20, kFailRobot = 5;
  for (int step = 1; step <= kSteps; ++step) {
    for (int robot = 0; robot < kRobots; ++robot) {
      const int burst = step == kBurstStep && robot == kBurstRobot ? kBurstFrames : 0;
      for (Frame& frame : RobotTraffic(scenario, robot, &robot_rngs[robot], burst)) {
        node_tap(robot).sent.push_back(frame);
        local_taps[robot].sent.push_back(std::move(frame));
      }
    }
    if (step == kFailStep) {
      local_taps[kFailRobot].read_errno = EIO;
      node_tap(kFailRobot).read_errno = EIO;
    }
    if (step == 10) {
      local.SetPosition(0, 200, 0, 1);
      remote.SetPosition(0, 200, 0, 1);
    }
    for (int node = 0; node < 2; ++node) ports.Receive(node, nodes[node].Drain());
    const TimeNs until_ns = step * scenario.network_step_ns;
    local.StepLockstep(until_ns);
    remote.StepLockstep(until_ns);
    for (int node = 0; node < 2; ++node) {
      const auto [writes, frames] = nodes[node].Write(ports.TakeWrites(node));
      writes_down += writes;
      frames_down += frames;
    }
  }

  ExpectSameLines(local_log.calls, remote_log.calls, "medium calls");
  ExpectSameLines(local_log.air, remote_log.air, "air frames");
  ExpectSameLines(local_log.deliveries, remote_log.deliveries, "deliveries");
  uint64_t oversize = 0, runts = 0, foreign = 0;
  for (int robot = 0; robot < kRobots; ++robot) {
    const std::string name = "robot " + std::to_string(robot);
    EXPECT_TRUE(local_taps[robot].written == node_tap(robot).written) << name << ": frames written";
    const tapbridge::PortCounters& l = local.port_counters(robot);
    const tapbridge::PortCounters& r = remote.port_counters(robot);
    // Not bytes_read: a node cuts an oversize frame, and the bridge counts the bytes it got.
    EXPECT_EQ(l.frames_read, r.frames_read) << name;
    EXPECT_EQ(l.oversize_dropped, r.oversize_dropped) << name;
    EXPECT_EQ(l.runt_dropped, r.runt_dropped) << name;
    EXPECT_EQ(l.unknown_source_dropped, r.unknown_source_dropped) << name;
    EXPECT_EQ(l.frames_written, r.frames_written) << name;
    EXPECT_EQ(l.attached, r.attached) << name;
    oversize += r.oversize_dropped;
    runts += r.runt_dropped;
    foreign += r.unknown_source_dropped;
  }

  // The run exercised what it claims to: traffic got through, every anomaly the bridge counts
  // occurred, the burst spilled into a second turn, the failed read detached the robot, and
  // broadcasts crossed once per node.
  EXPECT_GT(remote_log.deliveries.size(), 100u);  // Hundreds of frames were sent.
  EXPECT_GT(oversize, 0u);
  EXPECT_GT(runts, 0u);
  EXPECT_GT(foreign, 0u);
  EXPECT_GT(remote.port_counters(kBurstRobot).frames_read, static_cast<uint64_t>(kBurstFrames));
  EXPECT_FALSE(remote.port_counters(kFailRobot).attached);
  EXPECT_GT(ports.frames_dropped_closed(kFailRobot), 0u);
  EXPECT_LT(frames_down, writes_down);
}

}  // namespace
}  // namespace sitlnet::fleet

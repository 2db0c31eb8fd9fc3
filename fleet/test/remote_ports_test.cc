// A bridge over RemotePorts, fed as two node hosts would feed it, makes the same medium calls,
// air frames, deliveries and writes as a bridge whose robots' ports are on its own host (the
// identity that issue 35's byte-identical runs rest on).
#include <gtest/gtest.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <map>
#include <memory>
#include <vector>

#include "fleet/fleet.h"
#include "fleet/node_ports.h"
#include "fleet/test/bridge_fakes.h"

namespace sitlnet::fleet {
namespace {

using namespace test_support;

// What a node host does with its robots' TAPs (here in memory): NodePorts drains each one
// turn's budget, cutting frames longer than the link carries, and writes what comes down.
struct FakeNode {
  explicit FakeNode(NodeSlice slice)
      : ports(std::move(slice),
              [this](int robot) { return std::make_unique<MemoryPort>(&taps[robot]); }) {}
  std::map<int, MemoryTap> taps;  // Before ports, which open their ports on it.
  NodePorts ports;
};

TEST(RemotePorts, ABridgeOverTwoNodesDoesWhatItDoesOverLocalPorts) {
  const Scenario scenario = EightRobots();
  // Interleaved slices: the bridge's robot order is not the nodes' order.
  FakeNode n0({"n0", {0, 3, 5, 6}});
  FakeNode n1({"n1", {1, 2, 4, 7}});
  FakeNode* nodes[2] = {&n0, &n1};
  const auto node_tap = [&](int robot) -> MemoryTap& {
    return (std::ranges::count(n0.ports.slice().robots, robot) ? n0 : n1).taps[robot];
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
  RemotePorts ports(scenario, {n0.ports.slice(), n1.ports.slice()});
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
    proto::node::NodeFrames up;
    for (int node = 0; node < 2; ++node) {
      nodes[node]->ports.Drain(&up);
      ports.Receive(node, up);
    }
    const TimeNs until_ns = step * scenario.network_step_ns;
    local.StepLockstep(until_ns);
    remote.StepLockstep(until_ns);
    for (int node = 0; node < 2; ++node) {
      const proto::node::NodeWrites down = ports.TakeWrites(node);
      writes_down += down.writes_size();
      frames_down += down.frames_size();
      nodes[node]->ports.Write(down);
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
  EXPECT_LT(frames_down, writes_down);
  // NodePorts reads a failed robot no more; frames a node drained before it learnt of a detach
  // are dropped and counted, as a closed TAP drops its queue.
  proto::node::NodeFrames late;
  late.add_batches()->set_robot(kFailRobot);
  late.mutable_batches(0)->add_frames("late frame");
  ports.Receive(0, late);
  EXPECT_EQ(ports.frames_dropped_closed(kFailRobot), 1u);
}

bool PollsReadable(int fd) {
  pollfd polled{fd, POLLIN, 0};
  return poll(&polled, 1, 0) == 1;
}

// Realtime: a port polls readable exactly while frames wait (the bridge's realtime driver reads
// it then), and the ports measure how late each frame entered (now minus the node's read_ns, on
// the run's timebase), pass on how late the node wrote, and stamp each write with its instant.
TEST(RemotePorts, InRealtimeAPortPollsWhileFramesWaitAndTheLatenessIsMeasured) {
  const Scenario scenario = EightRobots();
  clock::Timebase timebase;
  timebase.Begin(MonotonicNowNs());
  RemotePorts ports(scenario, {{"n0", {0, 1}}, {"n1", {2, 3, 4, 5, 6, 7}}}, &timebase);
  const std::unique_ptr<tapbridge::Port> port = ports.Open(0);
  ASSERT_GE(port->fd(), 0);
  EXPECT_FALSE(PollsReadable(port->fd()));

  proto::node::NodeFrames frames;
  proto::node::FrameBatch* batch = frames.add_batches();
  batch->set_robot(0);
  for (int i = 0; i < 2; ++i) {
    const std::string frame(20, static_cast<char>('a' + i));
    batch->add_frames(frame);
    batch->add_read_ns(0);  // Read at virtual 0 on the node.
  }
  frames.add_write_late_ns(1 * kNsPerMs);
  frames.add_write_late_ns(3 * kNsPerMs);
  ports.Receive(0, frames);
  EXPECT_TRUE(PollsReadable(port->fd()));

  std::vector<uint8_t> buffer(64);
  const TimeNs before_ns = timebase.VirtualOf(MonotonicNowNs());
  EXPECT_EQ(port->Read(buffer), 20);
  EXPECT_TRUE(PollsReadable(port->fd()));  // One more waits.
  EXPECT_EQ(port->Read(buffer), 20);
  const TimeNs after_ns = timebase.VirtualOf(MonotonicNowNs());
  EXPECT_EQ(port->Read(buffer), 0);
  EXPECT_FALSE(PollsReadable(port->fd()));

  const tapbridge::LatenessStats entries = ports.LateEntries(0);
  EXPECT_EQ(entries.count, 2u);
  EXPECT_GE(entries.max_ns, before_ns);
  EXPECT_LE(entries.max_ns, after_ns);
  EXPECT_EQ(ports.LateEntries(1).count, 0u);
  const tapbridge::LatenessStats writes = ports.LateWrites(0);
  EXPECT_EQ(writes.count, 2u);
  EXPECT_EQ(writes.max_ns, 3 * kNsPerMs);

  const std::vector<uint8_t> delivery(20, 0x42);
  const TimeNs written_after_ns = timebase.VirtualOf(MonotonicNowNs());
  ASSERT_EQ(port->Write(delivery), 0);
  const TimeNs written_before_ns = timebase.VirtualOf(MonotonicNowNs());
  const proto::node::NodeWrites writes_down = ports.TakeWrites(0);
  ASSERT_EQ(writes_down.writes_size(), 1);
  EXPECT_GE(writes_down.writes(0).due_ns(), written_after_ns);
  EXPECT_LE(writes_down.writes(0).due_ns(), written_before_ns);
}

// In lockstep a port has no descriptor: only the lockstep driver reads it.
TEST(RemotePorts, InLockstepAPortHasNoDescriptor) {
  RemotePorts ports(EightRobots(), {{"n0", {0, 1, 2, 3, 4, 5, 6, 7}}});
  EXPECT_EQ(ports.Open(0)->fd(), -1);
  EXPECT_EQ(ports.LateEntries(0).count, 0u);
}

}  // namespace
}  // namespace sitlnet::fleet

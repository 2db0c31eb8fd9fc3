// What a node host sends its central (issue 35, docs/protocols.md "Central host <-> node host")
// is input: the node proved the shared secret, but it is another program on another host, and
// the link keeps the bounds of every other peer (docs/security.md). Here two nodes of a fleet
// (a, c on n0; b on n1) send, in any order, what the central checks with the production code:
// - a Hello (name, claimed robots, initial poses): RefuseNodeHello, as AcceptNodes does;
// - a CommandsCollected payload (lockstep) or an End payload (realtime): parsed as NodeFrames,
//   its writes' lateness checked against the Start's writes (FindBrokenWriteLateness, realtime)
//   and given to RemotePorts::Receive, as FleetPhysicsConnector does; or the bridge reading the
//   robots' ports (a turn each);
// - an End's poses: FindBrokenPoses, then PlacePoses among the fleet's, as Finish does.
// Whatever is accepted must keep the bounds: only a node's own robots, a turn of at most
// tapbridge::kMaxFramesPerRobotPerTurn frames of 1 to kMaxNodeFrameBytes bytes, no read instant
// or one per frame, a lateness per write of the Start at most; read by the bridge in the node's
// order (checked against a model queue), a port with frames waiting polls readable (realtime),
// each read instant and lateness counted once; a refused NodeFrames queues nothing; accepted
// poses are placed bit for bit where their robots are.
#include <fuzzer/FuzzedDataProvider.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"
#include "fleet/fleet.h"
#include "fleet/node_frames_bounds.h"
#include "fleet/node_hello_check.h"
#include "fleet/node_poses.h"
#include "fuzz/fuzz_inputs.h"

namespace {

namespace fleet = sitlnet::fleet;
namespace pn = sitlnet::proto::node;
namespace pc = sitlnet::proto::coord;

// Rare cases take the largest value of a range (fuzz_inputs.h).

// Longest refusal of a Hello in this fleet: names of 64 bytes at most (PrintableName) and robot
// lists that do not grow with the claim.
constexpr size_t kMaxRefusalBytes = 512;

// A robot index: the scenario's, just outside it, or anything.
int RobotIndex(FuzzedDataProvider& in) {
  return in.ConsumeBool() ? in.ConsumeIntegralInRange(-1, 3) : in.ConsumeIntegral<int>();
}

void FillHello(FuzzedDataProvider& in, pc::Hello* hello) {
  const std::vector<fleet::NodeSlice>& nodes = sitlnet::fuzz::ThreeRobotFleet().nodes;
  switch (in.ConsumeIntegralInRange(0, 2)) {
    case 0:
      hello->set_connector_name(nodes[in.ConsumeIntegralInRange<size_t>(0, 1)].name);
      break;
    case 1:
      hello->set_connector_name("n9");
      break;
    default:
      hello->set_connector_name(in.ConsumeRandomLengthString(80));
  }
  if (in.ConsumeBool()) {  // The robots of some node, as an honest node claims them.
    for (const int robot : nodes[in.ConsumeIntegralInRange<size_t>(0, 1)].robots) {
      hello->add_robots(robot);
    }
  } else {
    // A few, or many: a refusal must stay one line whatever the count.
    const int claimed = in.ConsumeIntegralInRange(0, 7) == 7 ? in.ConsumeIntegralInRange(6, 3000)
                                                             : in.ConsumeIntegralInRange(0, 5);
    for (int i = 0; i < claimed; ++i) hello->add_robots(RobotIndex(in));
  }
  sitlnet::fuzz::FillPoses(in, in.ConsumeIntegralInRange<size_t>(0, 3),
                           hello->mutable_initial_poses());
}

// A CommandsCollected payload: NodeFrames made up from the bytes, or the bytes as they come.
std::string FramesPayload(FuzzedDataProvider& in) {
  if (in.ConsumeIntegralInRange(0, 7) == 7) return in.ConsumeRandomLengthString(400);
  pn::NodeFrames frames;
  const int batches = in.ConsumeIntegralInRange(0, 4);
  for (int b = 0; b < batches; ++b) {
    pn::FrameBatch* batch = frames.add_batches();
    batch->set_robot(RobotIndex(in));
    // Sometimes a turn just over the bridge's, of small frames.
    const bool long_turn = in.ConsumeIntegralInRange(0, 15) == 15;
    const size_t count = long_turn ? sitlnet::tapbridge::kMaxFramesPerRobotPerTurn +
                                         in.ConsumeIntegralInRange<size_t>(0, 2)
                                   : in.ConsumeIntegralInRange<size_t>(0, 4);
    for (size_t i = 0; i < count; ++i) {
      if (long_turn) {
        batch->add_frames(std::string(1 + i % 3, static_cast<char>(i)));
      } else if (in.ConsumeIntegralInRange(0, 7) == 7) {  // Around the longest a node sends.
        batch->add_frames(
            std::string(fleet::kMaxNodeFrameBytes + in.ConsumeIntegralInRange(-1, 1), 'L'));
      } else {
        batch->add_frames(in.ConsumeRandomLengthString(120));
      }
    }
    // Realtime read instants: none (lockstep), one per frame, or one too many; near the run's
    // start, or anything.
    const int instants = in.ConsumeIntegralInRange(0, 7) == 7   ? batch->frames_size() + 1
                         : in.ConsumeIntegralInRange(0, 1) == 1 ? batch->frames_size()
                                                                : 0;
    for (int i = 0; i < instants; ++i) {
      batch->add_read_ns(in.ConsumeBool() ? in.ConsumeIntegralInRange<int64_t>(-1, 1'000'000'000)
                                          : in.ConsumeIntegral<int64_t>());
    }
    switch (in.ConsumeIntegralInRange(0, 3)) {
      case 0:
        batch->set_read_errno(EIO);
        break;
      case 1:
        batch->set_read_errno(in.ConsumeIntegral<int32_t>());
        break;
      default:
        break;  // The reads went well.
    }
  }
  const int late = in.ConsumeIntegralInRange(0, 4);  // Realtime: the writes' lateness.
  for (int i = 0; i < late; ++i) {
    frames.add_write_late_ns(in.ConsumeBool() ? in.ConsumeIntegralInRange<int64_t>(-1, 10'000'000)
                                              : in.ConsumeIntegral<int64_t>());
  }
  return frames.SerializeAsString();
}

// What the bridge would read from each robot's port, in order, as the model says the node sent.
struct RobotModel {
  std::unique_ptr<sitlnet::tapbridge::Port> port;  // Null: closed (detached).
  std::deque<std::string> queued;
  int read_errno = 0;
  int node = 0;
};

// What the central's lateness counts must hold, per node (realtime).
struct LatenessModel {
  uint64_t entries = 0;  // Frames read by the bridge (each came with its read instant).
  uint64_t writes = 0;   // Latenesses of writes accepted.
};

// One turn of the bridge on every open port; the frames must be the model's, in its order. In
// realtime a port with frames waiting polls readable, as a TAP does.
void ReadOneTurn(std::vector<RobotModel>& robots, bool realtime,
                 std::vector<LatenessModel>* lateness) {
  std::vector<uint8_t> buffer(fleet::kMaxNodeFrameBytes);
  for (RobotModel& robot : robots) {
    if (!robot.port) continue;
    if (realtime && !robot.queued.empty()) {
      pollfd ready{robot.port->fd(), POLLIN, 0};
      if (poll(&ready, 1, 0) != 1) __builtin_trap();
    }
    for (size_t turn = 0; turn < sitlnet::tapbridge::kMaxFramesPerRobotPerTurn; ++turn) {
      const ssize_t length = robot.port->Read(buffer);
      if (robot.queued.empty()) {
        if (length != -robot.read_errno) __builtin_trap();
        break;
      }
      const std::string& expected = robot.queued.front();
      if (length != static_cast<ssize_t>(expected.size()) ||
          std::memcmp(buffer.data(), expected.data(), expected.size()) != 0) {
        __builtin_trap();
      }
      robot.queued.pop_front();
      if (realtime) ++(*lateness)[robot.node].entries;
    }
  }
}

// The bounds of node_link.proto, as the model of this fuzzer states them: each batch for one of
// the node's robots, once; at most a bridge turn of frames of 1 to kMaxNodeFrameBytes bytes; an
// errno of 0 to 4095; in realtime one read instant per frame, in lockstep none.
bool KeepsBounds(const pn::NodeFrames& frames, const fleet::NodeSlice& slice, bool realtime) {
  std::vector<int> seen;
  for (const pn::FrameBatch& batch : frames.batches()) {
    if (std::ranges::find(slice.robots, batch.robot()) == slice.robots.end() ||
        std::ranges::find(seen, batch.robot()) != seen.end() ||
        batch.frames_size() > static_cast<int>(sitlnet::tapbridge::kMaxFramesPerRobotPerTurn) ||
        batch.read_errno() < 0 || batch.read_errno() > 4095) {
      return false;
    }
    seen.push_back(batch.robot());
    if (batch.read_ns_size() != (realtime ? batch.frames_size() : 0)) return false;
    for (const std::string& frame : batch.frames()) {
      if (frame.empty() || frame.size() > fleet::kMaxNodeFrameBytes) return false;
    }
  }
  return true;
}

// The model of FindBrokenPoses' second rule: every number a place a robot can be.
bool AllFinite(const pc::Poses& poses) {
  const auto finite = [](double x) { return x - x == 0; };  // NaN and infinities give NaN.
  return std::ranges::all_of(poses.position_m(), finite) &&
         std::ranges::all_of(poses.orientation_wxyz(), finite) &&
         std::ranges::all_of(poses.velocity_m_s(), finite);
}

void CheckPlaced(const pc::Poses& node, const std::vector<int>& robots, const pc::Poses& all,
                 size_t robot_count) {
  if (all.position_m_size() != static_cast<int>(3 * robot_count) ||
      all.orientation_wxyz_size() != static_cast<int>(4 * robot_count)) {
    __builtin_trap();
  }
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (size_t i = 0; i < robots.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (!same(all.position_m(3 * robots[i] + c), node.position_m(3 * i + c))) __builtin_trap();
    }
    for (int c = 0; c < 4; ++c) {
      if (!same(all.orientation_wxyz(4 * robots[i] + c), node.orientation_wxyz(4 * i + c))) {
        __builtin_trap();
      }
    }
  }
  if (node.velocity_m_s_size() == 0) return;
  if (all.velocity_m_s_size() != all.position_m_size()) __builtin_trap();
  for (size_t i = 0; i < robots.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (!same(all.velocity_m_s(3 * robots[i] + c), node.velocity_m_s(3 * i + c))) {
        __builtin_trap();
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const sitlnet::Scenario& scenario = sitlnet::fuzz::ThreeRobotFleet();
  const size_t robot_count = scenario.robots.size();
  FuzzedDataProvider in(data, size);
  // Realtime pacing: the run's timebase, begun as the coordinator begins it.
  // One input in eight: a realtime central's ports zero and scan two 100000-bucket histograms
  // per node (about 6 ms here, 20 times a lockstep input).
  const bool realtime = in.ConsumeIntegralInRange(0, 7) == 7;
  sitlnet::clock::Timebase timebase;
  timebase.Begin(sitlnet::MonotonicNowNs());
  fleet::RemotePorts ports(scenario, scenario.nodes, realtime ? &timebase : nullptr);
  std::vector<RobotModel> robots(robot_count);
  for (size_t r = 0; r < robot_count; ++r) {
    robots[r].port = ports.Open(static_cast<int>(r));
    robots[r].node = scenario.robots[r].node;
  }
  std::vector<LatenessModel> lateness(scenario.nodes.size());
  pc::Poses all;  // The fleet's poses, as FleetPhysicsConnector holds them: zeros to start.
  all.mutable_position_m()->Resize(static_cast<int>(3 * robot_count), 0.0);
  all.mutable_orientation_wxyz()->Resize(static_cast<int>(4 * robot_count), 0.0);

  while (in.remaining_bytes() > 0) {
    const int node = in.ConsumeIntegralInRange(0, 1);
    const fleet::NodeSlice& slice = scenario.nodes[node];
    switch (in.ConsumeIntegralInRange(0, 4)) {
      case 0: {
        pc::Hello hello;
        FillHello(in, &hello);
        // A refusal goes to the node and the central's log: one line, of a size the peer does
        // not set.
        if (const std::string refusal = fleet::RefuseNodeHello(scenario, scenario.nodes, hello);
            !refusal.empty()) {
          if (refusal.size() > kMaxRefusalBytes || refusal.find('\n') != std::string::npos) {
            __builtin_trap();
          }
          break;
        }
        // Accepted: one of the nodes, its robots exactly, poses of that many.
        const auto accepted =
            std::ranges::find(scenario.nodes, hello.connector_name(), &fleet::NodeSlice::name);
        if (accepted == scenario.nodes.end() ||
            !std::ranges::equal(hello.robots(), accepted->robots) ||
            fleet::FindBrokenPoses(hello.initial_poses(), accepted->robots.size())) {
          __builtin_trap();
        }
        fleet::PlacePoses(hello.initial_poses(), accepted->robots, &all);
        CheckPlaced(hello.initial_poses(), accepted->robots, all, robot_count);
        break;
      }
      case 1: {
        pn::NodeFrames frames;
        const int writes_sent = in.ConsumeIntegralInRange(0, 3);  // By the Start it answers.
        if (!frames.ParseFromString(FramesPayload(in))) break;    // Refused: no NodeFrames.
        if (realtime) {  // An End's frames: the writes' lateness first, as FleetPhysicsConnector.
          const bool reports_at_most_sent = frames.write_late_ns_size() <= writes_sent;
          if (fleet::FindBrokenWriteLateness(frames, writes_sent).has_value() ==
              reports_at_most_sent) {
            __builtin_trap();
          }
          if (!reports_at_most_sent) break;  // Refused: the link ends naming the node.
        }
        const bool keeps_bounds = KeepsBounds(frames, slice, realtime);
        try {
          ports.Receive(node, frames);
        } catch (const sitlnet::Error&) {
          if (keeps_bounds) __builtin_trap();
          break;  // Refused: the model queued nothing either.
        }
        if (!keeps_bounds) __builtin_trap();
        for (const pn::FrameBatch& batch : frames.batches()) {
          RobotModel& robot = robots[batch.robot()];
          if (!robot.port) continue;  // Dropped: the bridge closed it.
          robot.queued.insert(robot.queued.end(), batch.frames().begin(), batch.frames().end());
          if (batch.read_errno() != 0) robot.read_errno = batch.read_errno();
        }
        if (realtime) lateness[node].writes += frames.write_late_ns_size();
        break;
      }
      case 2:
        ReadOneTurn(robots, realtime, &lateness);
        break;
      case 3: {  // The bridge detaches a robot: its port closes, its queue goes.
        RobotModel& robot = robots[in.ConsumeIntegralInRange<size_t>(0, robot_count - 1)];
        robot.port.reset();
        robot.queued.clear();
        robot.read_errno = 0;
        break;
      }
      default: {
        pc::End end;
        if (in.ConsumeIntegralInRange(0, 7) == 7) {
          if (!end.ParseFromString(in.ConsumeRandomLengthString(200))) break;
        } else {
          sitlnet::fuzz::FillPoses(in, slice.robots.size(), end.mutable_poses());
        }
        const pc::Poses& poses = end.poses();
        const size_t n = slice.robots.size();
        const bool well_formed = poses.position_m_size() == static_cast<int>(3 * n) &&
                                 poses.orientation_wxyz_size() == static_cast<int>(4 * n) &&
                                 (poses.velocity_m_s_size() == 0 ||
                                  poses.velocity_m_s_size() == static_cast<int>(3 * n)) &&
                                 AllFinite(poses);
        if (fleet::FindBrokenPoses(poses, n).has_value() == well_formed) __builtin_trap();
        if (!well_formed) break;  // Refused: the run ends naming the node.
        fleet::PlacePoses(poses, slice.robots, &all);
        CheckPlaced(poses, slice.robots, all, robot_count);
      }
    }
  }
  // Each read instant and each lateness counted once, in realtime only.
  for (size_t node = 0; node < scenario.nodes.size(); ++node) {
    const int n = static_cast<int>(node);
    if (ports.LateEntries(n).count != (realtime ? lateness[node].entries : 0) ||
        ports.LateWrites(n).count != (realtime ? lateness[node].writes : 0)) {
      __builtin_trap();
    }
  }
  return 0;
}

// What a node may send up (node_link.proto's bounds): a NodeFrames that breaks one ends the link
// in one line naming the node, the robot and the bound, and none of it reaches the bridge; what
// only the robots or the bridge's own state explain is counted or passed on, never fatal.
#include "fleet/node_frames_bounds.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <string>

#include "fleet/fleet.h"

namespace sitlnet::fleet {
namespace {

Scenario FourRobots() {
  return LoadScenarioText(
      "name: \"bounds\" robot { name: \"a\" } robot { name: \"b\" } robot { name: \"c\" } "
      "robot { name: \"d\" }",
      "node_frames_bounds_test");
}

// Node n0 holds a and c; node n1 holds b and d.
class NodeFramesBounds : public ::testing::Test {
 protected:
  NodeFramesBounds()
      : scenario_(FourRobots()), ports_(scenario_, {{"n0", {0, 2}}, {"n1", {1, 3}}}) {
    for (int robot = 0; robot < 4; ++robot) open_.push_back(ports_.Open(robot));
  }

  // A batch for `robot` of `count` frames of `bytes` each.
  static proto::node::FrameBatch* AddBatch(proto::node::NodeFrames* frames, int robot, int count,
                                           size_t bytes) {
    proto::node::FrameBatch* batch = frames->add_batches();
    batch->set_robot(robot);
    for (int k = 0; k < count; ++k) batch->add_frames(std::string(bytes, 'x'));
    return batch;
  }

  // Node n0's message is refused with one line holding every part of `expected`.
  void ExpectRefused(const proto::node::NodeFrames& frames,
                     const std::vector<std::string>& expected) {
    try {
      ports_.Receive(0, frames);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string line = e.what();
      EXPECT_EQ(line.find('\n'), std::string::npos) << line;
      EXPECT_EQ(line.rfind("node 'n0' (robots a, c): ", 0), 0u) << line;
      for (const std::string& part : expected) {
        EXPECT_NE(line.find(part), std::string::npos) << "no \"" << part << "\" in: " << line;
      }
    }
  }

  // Frames robot `robot`'s port gives before it says none waits.
  int Readable(int robot) {
    std::vector<uint8_t> buffer(65536);
    int count = 0;
    while (open_[robot]->Read(buffer) > 0) ++count;
    return count;
  }

  Scenario scenario_;
  RemotePorts ports_;
  std::vector<std::unique_ptr<tapbridge::Port>> open_;
};

TEST_F(NodeFramesBounds, AFullTurnOfFullLengthFramesIsAccepted) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, tapbridge::kMaxFramesPerRobotPerTurn, kMaxNodeFrameBytes);
  AddBatch(&frames, 2, 1, 1);
  ports_.Receive(0, frames);
  EXPECT_EQ(Readable(0), static_cast<int>(tapbridge::kMaxFramesPerRobotPerTurn));
  EXPECT_EQ(Readable(2), 1);
}

TEST_F(NodeFramesBounds, FramesForARobotOfAnotherNodeAreRefused) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 1, 1, 60);
  ExpectRefused(frames, {"robot 'b'", "not one of its robots"});
}

TEST_F(NodeFramesBounds, FramesForARobotOutsideTheScenarioAreRefused) {
  for (const int robot : {4, -1}) {
    proto::node::NodeFrames frames;
    AddBatch(&frames, robot, 1, 60);
    ExpectRefused(frames, {"robot " + std::to_string(robot), "not in the scenario (4 robots)"});
  }
}

TEST_F(NodeFramesBounds, TwoBatchesForOneRobotAreRefused) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 2, 1, 60);
  AddBatch(&frames, 2, 1, 60);
  ExpectRefused(frames, {"two batches", "robot 'c'"});
}

TEST_F(NodeFramesBounds, MoreFramesThanOneTurnIsRefused) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 2, tapbridge::kMaxFramesPerRobotPerTurn + 1, 60);
  ExpectRefused(frames, {"257 frames", "robot 'c'", "(256)"});
}

TEST_F(NodeFramesBounds, AFrameLongerThanACutOneIsRefused) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, 1, kMaxNodeFrameBytes + 1);
  ExpectRefused(frames, {std::to_string(kMaxNodeFrameBytes + 1) + " bytes", "robot 'a'"});
}

TEST_F(NodeFramesBounds, AnEmptyFrameIsRefused) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, 1, 0);
  ExpectRefused(frames, {"empty frame", "robot 'a'"});
}

TEST_F(NodeFramesBounds, AReadErrnoThatIsNoErrnoIsRefused) {
  for (const int read_errno : {-5, 4096}) {
    proto::node::NodeFrames frames;
    AddBatch(&frames, 0, 0, 0)->set_read_errno(read_errno);
    ExpectRefused(frames, {"read_errno " + std::to_string(read_errno), "robot 'a'"});
  }
}

TEST_F(NodeFramesBounds, NothingOfARefusedMessageIsQueued) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, 3, 60);  // Within bounds, but in the same message as the next.
  AddBatch(&frames, 1, 1, 60);
  ExpectRefused(frames, {"robot 'b'"});
  EXPECT_EQ(Readable(0), 0);
}

TEST_F(NodeFramesBounds, ACutFrameIsDroppedAsOversizeByTheBridge) {
  tapbridge::BridgeOptions options;
  options.open_port = [this](int robot) { return ports_.Open(robot); };
  open_.clear();  // The bridge opens the ports itself.
  tapbridge::BridgeCore core(
      scenario_, tapbridge::MakeRelayMedium({RobotMac(0), RobotMac(1), RobotMac(2), RobotMac(3)}),
      options);
  core.AttachAll();
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, 1, kMaxNodeFrameBytes);
  ports_.Receive(0, frames);
  core.StepLockstep(scenario_.network_step_ns);
  EXPECT_EQ(core.port_counters(0).frames_read, 1u);
  EXPECT_EQ(core.port_counters(0).oversize_dropped, 1u);
}

// Hot path: the node cannot know yet that the bridge closed a port, so its frames are dropped
// and counted, as a closed TAP drops them; a failed read comes out after the frames before it.
TEST_F(NodeFramesBounds, FramesForAClosedPortAreCountedAndAFailedReadFollowsItsFrames) {
  proto::node::NodeFrames frames;
  AddBatch(&frames, 0, 2, 60)->set_read_errno(EIO);
  AddBatch(&frames, 2, 3, 60);
  open_[2].reset();
  ports_.Receive(0, frames);
  EXPECT_EQ(ports_.frames_dropped_closed(2), 3u);
  EXPECT_EQ(ports_.frames_dropped_closed(0), 0u);
  EXPECT_EQ(Readable(0), 2);
  std::vector<uint8_t> buffer(64);
  EXPECT_EQ(open_[0]->Read(buffer), -EIO);
  // Reopened, the port starts empty: what the old one held went with it.
  open_[0].reset();
  open_[0] = ports_.Open(0);
  EXPECT_EQ(open_[0]->Read(buffer), 0);
}

// Realtime: each frame's read instant, or a frame would be timed by another's (a batch without
// them let the next batch's instants time its frames; found while writing the model of
// fuzz/node_to_central_fuzz.cc, not by a run). Lockstep: none.
TEST(FindBrokenBound, WantsOneReadInstantPerFrameInRealtimeAndNoneInLockstep) {
  const Scenario scenario = FourRobots();
  const std::vector<std::string> names = {"a", "b", "c", "d"};
  const NodeSlice n0{"n0", {0, 2}};
  proto::node::NodeFrames frames;
  proto::node::FrameBatch* batch = frames.add_batches();
  batch->set_robot(0);
  batch->add_frames("one");
  batch->add_frames("two");
  EXPECT_EQ(FindBrokenBound(frames, n0, names, /*realtime=*/false), std::nullopt);
  EXPECT_EQ(FindBrokenBound(frames, n0, names, /*realtime=*/true),
            "sent 0 read instants for 2 frames of robot 'a'");
  batch->add_read_ns(5);
  EXPECT_EQ(FindBrokenBound(frames, n0, names, /*realtime=*/true),
            "sent 1 read instants for 2 frames of robot 'a'");
  batch->add_read_ns(6);
  EXPECT_EQ(FindBrokenBound(frames, n0, names, /*realtime=*/true), std::nullopt);
  EXPECT_EQ(FindBrokenBound(frames, n0, names, /*realtime=*/false),
            "sent 2 read instants for 2 frames of robot 'a'");
}

TEST(FindBrokenWriteLateness, AtMostOneLatenessPerWriteOfTheStart) {
  proto::node::NodeFrames frames;
  EXPECT_EQ(FindBrokenWriteLateness(frames, 0), std::nullopt);
  frames.add_write_late_ns(0);
  frames.add_write_late_ns(3 * kNsPerMs);
  EXPECT_EQ(FindBrokenWriteLateness(frames, 2), std::nullopt);
  EXPECT_EQ(FindBrokenWriteLateness(frames, 1), "reports 2 writes, but its Start carried 1");
}

}  // namespace
}  // namespace sitlnet::fleet

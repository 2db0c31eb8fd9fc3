// The node host's ports: one bridge turn per robot and drain, frames cut as the link carries
// them, a failed robot read no more, refused writes leaving nothing written; and NodeSimulator's
// order: the Start's writes before the physics, the drain when the commands are in.
#include "fleet/node_ports.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "fleet/node_frames_bounds.h"
#include "fleet/test/bridge_fakes.h"

namespace sitlnet::fleet {
namespace {

using namespace test_support;

// A node of robots 2 and 5 whose ports are in-memory taps.
struct TwoRobotNode {
  TwoRobotNode()
      : ports({"n", {2, 5}},
              [this](int robot) { return std::make_unique<MemoryPort>(&taps[robot]); }) {}
  std::map<int, MemoryTap> taps;  // Before ports, which open their ports on it.
  NodePorts ports;
};

TEST(NodePorts, ADrainTakesOneTurnPerRobotCutsLongFramesAndReadsAFailedRobotNoMore) {
  TwoRobotNode node;
  const size_t turn = tapbridge::kMaxFramesPerRobotPerTurn;
  for (size_t i = 0; i < turn + 40; ++i) node.taps[2].sent.push_back(Frame(60, 1));
  node.taps[2].sent.push_back(Frame(3000, 2));  // Longer than any 802.11 frame carries.
  node.taps[5].sent = {Frame(70, 3), Frame(80, 4)};
  node.taps[5].read_errno = EIO;

  proto::node::NodeFrames frames;
  node.ports.Drain(&frames);
  ASSERT_EQ(frames.batches_size(), 2);
  EXPECT_EQ(frames.batches(0).robot(), 2);
  EXPECT_EQ(frames.batches(0).frames_size(), static_cast<int>(turn));
  EXPECT_EQ(frames.batches(0).read_errno(), 0);
  EXPECT_EQ(frames.batches(1).robot(), 5);
  EXPECT_EQ(frames.batches(1).frames_size(), 2);  // Its frames, then the failure.
  EXPECT_EQ(frames.batches(1).read_errno(), EIO);

  node.taps[5].sent.push_back(Frame(90, 5));
  node.ports.Drain(&frames);
  ASSERT_EQ(frames.batches_size(), 1);  // Robot 5 is read no more.
  EXPECT_EQ(frames.batches(0).frames_size(), 41);
  EXPECT_EQ(frames.batches(0).frames(40).size(), kMaxNodeFrameBytes);
  EXPECT_EQ(node.taps[5].sent.size(), 1u);

  node.ports.Drain(&frames);
  EXPECT_EQ(frames.batches_size(), 0);  // Nothing to say, no batch.
}

TEST(NodePorts, AWriteToAnotherRobotOrOfAMissingFrameIsRefusedWithNothingWritten) {
  TwoRobotNode node;
  proto::node::NodeWrites writes;
  writes.add_frames("frame");
  proto::node::NodeWrites::Write* first = writes.add_writes();
  first->set_robot(2);
  first->set_frame_index(0);
  proto::node::NodeWrites::Write* second = writes.add_writes();
  second->set_robot(3);
  second->set_frame_index(0);
  try {
    node.ports.Write(writes);
    ADD_FAILURE() << "wrote to robot 3";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "the coordinator wrote to robot 3, which is not one of this node's");
  }
  second->set_robot(5);
  second->set_frame_index(1);
  try {
    node.ports.Write(writes);
    ADD_FAILURE() << "wrote a frame that is not there";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "the coordinator wrote frame 1 of 1");
  }
  EXPECT_TRUE(node.taps[2].written.empty());
  second->set_frame_index(0);
  node.ports.Write(writes);
  EXPECT_EQ(node.taps[2].written, std::vector<Frame>{Frame({'f', 'r', 'a', 'm', 'e'})});
  EXPECT_EQ(node.taps[5].written, node.taps[2].written);
}

// Physics that sees what robot 2 was written when it starts, then robot 2 sends a frame before
// its command; `collect`: it reports CommandsCollected itself.
class RecordingPhysics final : public coordinator::Simulator {
 public:
  RecordingPhysics(MemoryTap* tap, bool collect) : tap_(tap), collect_(collect) {}
  void RunIteration(const proto::coord::Start&, proto::coord::End*,
                    coordinator::IterationContext& context) override {
    written_at_start = tap_->written.size();
    tap_->sent.push_back(Frame(64, 7));
    if (collect_) context.CommandsCollected();
  }
  size_t written_at_start = 0;

 private:
  MemoryTap* tap_;
  bool collect_;
};

// The link's side of CommandsCollected: each payload reported.
class PayloadLog final : public coordinator::IterationContext {
 public:
  void CommandsCollected() override { payloads.emplace_back(); }
  void CommandsCollectedWithPayload(std::string payload) override {
    payloads.push_back(std::move(payload));
  }
  std::vector<std::string> payloads;
};

// Realtime: a Start whose end lies before any wall instant (a broken central's) puts the read's
// deadline at the smallest TimeNs; subtracting now from it overflowed (found by
// fuzz/central_to_node_fuzz.cc under UBSan), and the wrapped wait was centuries long. The read
// makes its one pass and returns: the child gets 5 s before SIGALRM fails the test.
TEST(NodePorts, AReadUntilAnInstantBeforeAnyWallTimeMakesOnePassAndReturns) {
  EXPECT_EXIT(
      {
        alarm(5);
        TwoRobotNode node;
        node.taps[2].sent.push_back(Frame(60, 1));
        clock::Timebase timebase;
        timebase.Begin(MonotonicNowNs());
        proto::node::NodeFrames frames;
        node.ports.ReadUntil(std::numeric_limits<TimeNs>::min(), timebase, &frames);
        std::_Exit(frames.batches_size() == 0 ? 0 : 1);  // Memory taps never poll readable.
      },
      ::testing::ExitedWithCode(0), "");
}

TEST(NodeSimulator, WritesTheStartsFramesBeforeThePhysicsAndSendsTheDrainWithTheCommands) {
  for (const bool physics_collects : {true, false}) {
    TwoRobotNode node;
    RecordingPhysics physics(&node.taps[2], physics_collects);
    NodeSimulator simulator(&physics, &node.ports);
    proto::node::NodeStart node_start;
    node_start.mutable_writes()->add_frames("delivered");
    proto::node::NodeWrites::Write* write = node_start.mutable_writes()->add_writes();
    write->set_robot(2);
    write->set_frame_index(0);
    proto::coord::Start start;
    start.set_iteration(4);
    node_start.SerializeToString(start.mutable_payload());
    proto::coord::End end;
    PayloadLog context;
    simulator.RunIteration(start, &end, context);

    EXPECT_EQ(physics.written_at_start, 1u) << physics_collects;
    ASSERT_EQ(context.payloads.size(), 1u) << physics_collects;  // Once, either way.
    proto::node::NodeFrames frames;
    ASSERT_TRUE(frames.ParseFromString(context.payloads[0]));
    ASSERT_EQ(frames.batches_size(), 1);
    EXPECT_EQ(frames.batches(0).robot(), 2);
    EXPECT_EQ(frames.batches(0).frames(0), std::string(64, 7));
  }
}

TEST(NodeSimulator, AStartWhosePayloadDoesNotParseIsRefused) {
  TwoRobotNode node;
  RecordingPhysics physics(&node.taps[2], true);
  NodeSimulator simulator(&physics, &node.ports);
  proto::coord::Start start;
  start.set_iteration(4);
  start.set_payload(
      "\x0a\x05"
      "ab");  // A field of 5 bytes with 2 left.
  proto::coord::End end;
  PayloadLog context;
  try {
    simulator.RunIteration(start, &end, context);
    ADD_FAILURE() << "ran an iteration on a broken Start";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "the coordinator's Start of iteration 4 carries no NodeStart that parses");
  }
  EXPECT_TRUE(context.payloads.empty());
}

}  // namespace
}  // namespace sitlnet::fleet

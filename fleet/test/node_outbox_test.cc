// The way down: what the bridge writes to a node's robots goes as one NodeWrites per node, in
// write order, each distinct frame once (a broadcast crosses once per node, not per receiver).
#include <gtest/gtest.h>

#include <string>

#include "fleet/fleet.h"

namespace sitlnet::fleet {
namespace {

std::span<const uint8_t> Bytes(const std::string& text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

// "robot:frame" for each write, the frame spelled out from the message's frame list.
std::vector<std::string> Writes(const proto::node::NodeWrites& down) {
  std::vector<std::string> writes;
  for (const proto::node::NodeWrites::Write& write : down.writes()) {
    writes.push_back(std::to_string(write.robot()) + ":" + down.frames(write.frame_index()));
  }
  return writes;
}

TEST(NodeOutbox, ABroadcastCrossesOncePerNodeAndWritesKeepTheirOrder) {
  const Scenario scenario = LoadScenarioText(
      "name: \"down\" robot { name: \"a\" } robot { name: \"b\" } robot { name: \"c\" } "
      "robot { name: \"d\" }",
      "node_outbox_test");
  RemotePorts ports(scenario, {{"n0", {0, 2, 3}}, {"n1", {1}}});
  std::vector<std::unique_ptr<tapbridge::Port>> open;
  for (int robot = 0; robot < 4; ++robot) open.push_back(ports.Open(robot));

  const std::string broadcast = "broadcast from b";
  const std::string unicast = "unicast to c";
  for (const int robot : {0, 2, 3}) EXPECT_EQ(open[robot]->Write(Bytes(broadcast)), 0);
  EXPECT_EQ(open[2]->Write(Bytes(unicast)), 0);
  EXPECT_EQ(open[0]->Write(Bytes(broadcast)), 0);  // The same bytes again, later.
  EXPECT_EQ(open[1]->Write(Bytes(unicast)), 0);

  const proto::node::NodeWrites n0 = ports.TakeWrites(0);
  EXPECT_EQ(n0.frames_size(), 2);
  EXPECT_EQ(Writes(n0),
            (std::vector<std::string>{"0:" + broadcast, "2:" + broadcast, "3:" + broadcast,
                                      "2:" + unicast, "0:" + broadcast}));
  const proto::node::NodeWrites n1 = ports.TakeWrites(1);
  EXPECT_EQ(Writes(n1), (std::vector<std::string>{"1:" + unicast}));

  // Taken: the next message starts empty and lists its own frames.
  EXPECT_EQ(ports.TakeWrites(0).writes_size(), 0);
  EXPECT_EQ(open[3]->Write(Bytes(unicast)), 0);
  const proto::node::NodeWrites next = ports.TakeWrites(0);
  EXPECT_EQ(next.frames_size(), 1);
  EXPECT_EQ(Writes(next), (std::vector<std::string>{"3:" + unicast}));
}

}  // namespace
}  // namespace sitlnet::fleet

// The central's check of a node's Hello, without sockets (the refusals over a link:
// fleet_link_test.cc, AcceptNodes).
#include "fleet/node_hello_check.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fleet/test/bridge_fakes.h"

namespace sitlnet::fleet {
namespace {

using test_support::EightRobots;

const std::vector<NodeSlice> kNodes = {{"n0", {0, 3, 5, 6}}, {"n1", {1, 2, 4, 7}}};

// A Hello of node `name` claiming `robots`, with their initial poses (no velocities).
proto::coord::Hello HelloOf(const std::string& name, const std::vector<int>& robots) {
  proto::coord::Hello hello;
  hello.set_connector_name(name);
  hello.mutable_robots()->Add(robots.begin(), robots.end());
  hello.mutable_initial_poses()->mutable_position_m()->Resize(3 * robots.size(), 0.0);
  hello.mutable_initial_poses()->mutable_orientation_wxyz()->Resize(4 * robots.size(), 0.0);
  return hello;
}

TEST(RefuseNodeHello, AcceptsANodeClaimingExactlyItsRobots) {
  EXPECT_EQ(RefuseNodeHello(EightRobots(), kNodes, HelloOf("n1", {1, 2, 4, 7})), "");
}

// Found by fuzz/node_to_central_fuzz.cc: a refusal listed every robot of the claim, so a Hello of
// a million robots made a line of megabytes, logged and sent back as the Error message.
TEST(RefuseNodeHello, AClaimOfAMillionRobotsIsRefusedInOneShortLine) {
  const std::vector<int> claimed(1'000'000, 3);
  const std::string refusal = RefuseNodeHello(EightRobots(), kNodes, HelloOf("n1", claimed));
  EXPECT_EQ(refusal,
            "node 'n1' claims robots r3, r3, r3, r3, r3, r3, r3, r3 and 999992 more, but the "
            "scenario gives it r1, r2, r4, r7 (another scenario or --node?)");
}

TEST(RefuseNodeHello, PosesOfAnotherCountAreRefusedNamingTheNode) {
  proto::coord::Hello hello = HelloOf("n0", {0, 3, 5, 6});
  hello.mutable_initial_poses()->add_velocity_m_s(1);
  EXPECT_EQ(RefuseNodeHello(EightRobots(), kNodes, hello),
            "node 'n0' (robots r0, r3, r5, r6): initial poses: sent 12 position, 16 orientation "
            "and 1 velocity numbers, not 3, 4 and 3 (or 0) for each of its 4 robots");
}

}  // namespace
}  // namespace sitlnet::fleet

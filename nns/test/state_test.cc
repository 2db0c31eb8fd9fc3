// The state file round-trips and robot names resolve as docs/cli.md says.
#include <gtest/gtest.h>

#include "nns/nns.h"

namespace sitlnet::nns {
namespace {

Scenario TwoRobots(const std::string& name) {
  return LoadScenarioText("name: \"" + name +
                              "\" robot { name: \"a\" } robot { name: \"b\" } "
                              "addresses { physics_port: 9600 }",
                          name + ".textproto");
}

TEST(StateTest, RoundTripsEveryField) {
  ScenarioState state = StateFromScenario(TwoRobots("alpha"));
  state.source_path = "/tmp/dir with space/alpha.textproto";
  const ScenarioState back = ParseState(FormatState(state), "state");
  EXPECT_EQ(back.name, "alpha");
  EXPECT_EQ(back.source_path, state.source_path);
  EXPECT_EQ(back.physics_port, 9600);
  ASSERT_EQ(back.robots.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.robots[i].index, state.robots[i].index);
    EXPECT_EQ(back.robots[i].name, state.robots[i].name);
    EXPECT_EQ(back.robots[i].netns, state.robots[i].netns);
    EXPECT_EQ(back.robots[i].root_veth, state.robots[i].root_veth);
    EXPECT_EQ(back.robots[i].wlan_address, state.robots[i].wlan_address);
    EXPECT_EQ(back.robots[i].ctl_root_address, state.robots[i].ctl_root_address);
    EXPECT_EQ(back.robots[i].ctl_robot_address, state.robots[i].ctl_robot_address);
  }
  EXPECT_EQ(back.robots[1].netns, "alpha-b");
  EXPECT_EQ(back.PhysicsAddress(back.robots[1]),
            FormatIpv4(state.robots[1].ctl_root_address) + ":9600");
}

TEST(StateTest, MalformedLineNamesFileAndLine) {
  try {
    ParseState("scenario x\nrobot 0 a\n", "/run/sitlnet/x/state");
    FAIL() << "accepted a truncated robot line";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/run/sitlnet/x/state:2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseState("physics_port 1\n", "s"), Error);  // No scenario name.
  EXPECT_THROW(ParseState("scenario x\nbogus 1\n", "s"), Error);
}

TEST(StateTest, ResolvesPlainQualifiedAndScopedNames) {
  const std::vector<ScenarioState> up = {StateFromScenario(TwoRobots("one")),
                                         StateFromScenario(TwoRobots("two"))};
  EXPECT_EQ(ResolveRobot(up, "two-b").robot.netns, "two-b");
  EXPECT_EQ(ResolveRobot(up, "a", "one").robot.netns, "one-a");
  EXPECT_EQ(ResolveRobot(up, "b", "two").scenario.name, "two");
  // "a" exists in both scenarios: ambiguous, and the message lists both.
  try {
    ResolveRobot(up, "a");
    FAIL() << "ambiguous name accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("one-a, two-a"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ResolveRobot({up[0]}, "a").robot.netns, "one-a");
  EXPECT_THROW(ResolveRobot(up, "zz"), Error);
  EXPECT_THROW(ResolveRobot(up, "a", "three"), Error);
}

}  // namespace
}  // namespace sitlnet::nns

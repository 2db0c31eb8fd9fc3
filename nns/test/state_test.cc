// The state file round-trips and robot names resolve as docs/cli.md says.
#include <gtest/gtest.h>

#include <algorithm>

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

// A node host's state (issue 35) lists its slice only, with the robots' global indices and
// names, and reads back so.
TEST(StateTest, ASliceListsOnlyItsRobotsWithTheirGlobalIndices) {
  const Scenario scenario = LoadScenarioText(
      "name: \"beta\" robot { name: \"a\" } robot { name: \"b\" } robot { name: \"c\" }",
      "beta.textproto");
  const ScenarioState state = ParseState(FormatState(StateFromScenario(scenario, {1})), "state");
  ASSERT_EQ(state.robots.size(), 1u);
  EXPECT_EQ(state.robots[0].index, 1);
  EXPECT_EQ(state.robots[0].name, "b");
  EXPECT_EQ(state.robots[0].netns, "beta-b");
  EXPECT_EQ(state.robots[0].root_veth, "beta-c1");
  EXPECT_EQ(state.robots[0].wlan_address, scenario.robots[1].wlan_address);
  EXPECT_EQ(StateFromScenario(scenario).robots.size(), 3u);
  EXPECT_THROW(StateFromScenario(scenario, {2, 0}), Error);  // Not ascending.
  EXPECT_THROW(StateFromScenario(scenario, {3}), Error);     // No such robot.
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

// Audit finding 5: a newline in the scenario's path was written raw and read back as a robot
// line, which `down` then tore down (a namespace and a link it never created, e.g. docker0).
TEST(StateTest, ANewlineInTheSourcePathCannotAddARobot) {
  ScenarioState state = StateFromScenario(TwoRobots("alpha"));
  state.source_path =
      "/tmp/x\nrobot 2 z alpha-z docker0 10.0.0.1 10.0.0.2 10.0.0.3\nsource /tmp/%41.textproto";
  const std::string text = FormatState(state);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 6) << text;  // Comment, 4 facts, source.
  const ScenarioState back = ParseState(text, "state");
  EXPECT_EQ(back.robots.size(), 2u);
  EXPECT_EQ(back.source_path, state.source_path);
}

TEST(StateTest, RobotLinesMustNameThePlansNamespaceAndVeth) {
  const std::string head = "scenario alpha\nphysics_port 9600\n";
  const std::string addresses = " 10.0.0.1 10.0.0.2 10.0.0.3\n";
  EXPECT_NO_THROW(ParseState(head + "robot 0 a alpha-a alpha-c0" + addresses, "s"));
  for (const char* forged : {"robot 0 a alpha-a docker0", "robot 0 a other-a alpha-c0",
                             "robot 1 a alpha-a alpha-c0", "robot -1 a alpha-a alpha-c-1"}) {
    EXPECT_THROW(ParseState(head + forged + addresses, "s"), Error) << forged;
  }
  EXPECT_THROW(ParseState("robot 0 a alpha-a alpha-c0" + addresses + head, "s"), Error)
      << "a robot line before the scenario's name cannot be checked";
  // Found by state_file_fuzz: a second scenario line after the robots renamed the scenario
  // under them, and `down` of the new name would have removed the old one's namespaces.
  EXPECT_THROW(ParseState(head + "robot 0 a alpha-a alpha-c0" + addresses + "scenario beta\n", "s"),
               Error);
  EXPECT_THROW(
      ParseState(head + "robot 0 a alpha-a alpha-c0 10.0.0.1 10.0.0.2 10.0.0.3 extra\n", "s"),
      Error);
  EXPECT_THROW(ParseState(head + "source /tmp/%4\n", "s"), Error);
  EXPECT_THROW(ParseState(head + "source /tmp/%zz\n", "s"), Error);
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

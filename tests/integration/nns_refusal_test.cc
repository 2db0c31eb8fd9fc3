// Refusals touch nothing: missing privileges, a host route clash, a
// namespace with our name that the scenario did not create. What is not a clash: another
// scenario on the same subnets, a host device named like a root-side veth.
#include <linux/capability.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

bool Contains(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

void ExpectNothingCreated(const Scenario& s) {
  for (const RobotPlan& robot : s.robots) {
    EXPECT_FALSE(NetnsExists(robot.netns)) << robot.netns;
  }
  EXPECT_FALSE(NetnsExists(CtlNetnsName(s.name)));
  EXPECT_FALSE(StateExists(s.name));
}

int Lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

TEST(NnsRefusalTest, MissingPrivilegesGiveOneLineNamingThemAndTheFix) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("prv", 0, 1);
  DownGuard guard(test.scenario.name);
  // Every capability gone (root without capabilities, as in a locked-down container).
  const CommandResult none = RunWithoutCapabilities({SitlnetBinary(), "up", test.path}, ~0ull);
  EXPECT_EQ(none.exit_code, 3) << none.err;
  EXPECT_EQ(Lines(none.err), 1) << none.err;
  for (const char* needle : {"CAP_NET_ADMIN", "CAP_SYS_ADMIN", "sudo", "--cap-add NET_ADMIN",
                             "--cap-add SYS_ADMIN", "--device /dev/net/tun"}) {
    EXPECT_TRUE(Contains(none.err, needle)) << needle << " missing from: " << none.err;
  }
  // Only CAP_SYS_ADMIN gone: the line names exactly that.
  const CommandResult no_sys =
      RunWithoutCapabilities({SitlnetBinary(), "up", test.path}, 1ull << CAP_SYS_ADMIN);
  EXPECT_EQ(no_sys.exit_code, 3) << no_sys.err;
  EXPECT_TRUE(Contains(no_sys.err, "missing CAP_SYS_ADMIN:")) << no_sys.err;
  EXPECT_FALSE(Contains(no_sys.err, "CAP_NET_ADMIN")) << no_sys.err;
  for (const char* command : {"down", "status"}) {
    const CommandResult other =
        RunWithoutCapabilities({SitlnetBinary(), command, test.scenario.name}, ~0ull);
    EXPECT_EQ(other.exit_code, 3) << command << ": " << other.err;
    EXPECT_EQ(Lines(other.err), 1) << other.err;
  }
  ExpectNothingCreated(test.scenario);
}

TEST(NnsRefusalTest, AddressClashWithAHostRouteIsRefusedAndNothingTouched) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  TestScenario test = MakeScenario("clh", 1, 2);
  // A blackhole route of our own making over the scenario's wlan subnet:
  // independent of this machine's routes, removed by exact prefix.
  const std::string prefix = FormatIpv4Prefix(test.scenario.wlan_subnet);
  ASSERT_EQ(RunCommand({"ip", "route", "add", "blackhole", prefix}).exit_code, 0);
  CommandGuard route_guard({"ip", "route", "del", "blackhole", prefix});
  DownGuard guard(test.scenario.name);
  const CommandResult up = RunCommand({SitlnetBinary(), "up", test.path});
  EXPECT_EQ(up.exit_code, 1);
  EXPECT_EQ(Lines(up.err), 1) << up.err;
  EXPECT_TRUE(Contains(up.err, "overlaps host route " + prefix)) << up.err;
  ExpectNothingCreated(test.scenario);
}

// Each scenario's ctl links end in its own ctl namespace, and its wlan subnet lives in its
// robots' namespaces: two scenarios with the same subnets do not meet (before the ctl namespace,
// the second was refused because the first's root-side routes were in the host's table).
TEST(NnsRefusalTest, ASecondScenarioOnTheSameSubnetsComesUpBesideTheFirst) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario first = MakeScenario("sba", 4, 2);
  const TestScenario second = MakeScenario("sbb", 4, 2);  // Same slot: same subnets.
  DownGuard guard_first(first.scenario.name);
  DownGuard guard_second(second.scenario.name);
  Up(first.scenario);
  const CommandResult up = RunCommand({SitlnetBinary(), "up", second.path});
  EXPECT_EQ(up.exit_code, 0) << up.err;
  for (const TestScenario* test : {&first, &second}) {
    for (const RobotPlan& robot : test->scenario.robots) {
      EXPECT_EQ(UdpRoundTrip(test->scenario.name, robot.netns, robot.ctl_robot_address), "")
          << test->scenario.name << " " << robot.name;
    }
  }
}

TEST(NnsRefusalTest, ForeignNamespaceWithOurNameIsRefusedAndLeftAlone) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("fns", 2, 3);
  const std::string foreign = test.scenario.robots[1].netns;
  ASSERT_EQ(RunCommand({"ip", "netns", "add", foreign}).exit_code, 0);
  CommandGuard netns_guard({"ip", "netns", "del", foreign});
  DownGuard guard(test.scenario.name);
  const CommandResult up = RunCommand({SitlnetBinary(), "up", test.path});
  EXPECT_EQ(up.exit_code, 1);
  EXPECT_EQ(Lines(up.err), 1) << up.err;
  EXPECT_TRUE(Contains(up.err, "\"" + foreign + "\"")) << up.err;
  EXPECT_TRUE(Contains(up.err, "did not create it")) << up.err;
  EXPECT_TRUE(NetnsExists(foreign));
  // down of the scenario does not touch it either: it is not in any state.
  EXPECT_EQ(RunCommand({SitlnetBinary(), "down", test.scenario.name}).exit_code, 0);
  EXPECT_TRUE(NetnsExists(foreign));
  for (const RobotPlan& robot : test.scenario.robots) {
    if (robot.netns != foreign) {
      EXPECT_FALSE(NetnsExists(robot.netns)) << robot.netns;
    }
  }
  EXPECT_FALSE(StateExists(test.scenario.name));
}

TEST(NnsRefusalTest, AForeignCtlNamespaceIsRefusedAndAHostDeviceWithAVethsNameIsLeftAlone) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("fdv", 3, 2);
  DownGuard guard(test.scenario.name);
  {
    const std::string foreign = CtlNetnsName(test.scenario.name);
    ASSERT_EQ(RunCommand({"ip", "netns", "add", foreign}).exit_code, 0);
    CommandGuard netns_guard({"ip", "netns", "del", foreign});
    const CommandResult up = RunCommand({SitlnetBinary(), "up", test.path});
    EXPECT_EQ(up.exit_code, 1);
    EXPECT_EQ(Lines(up.err), 1) << up.err;
    EXPECT_TRUE(Contains(up.err, "namespace \"" + foreign + "\"")) << up.err;
    EXPECT_TRUE(Contains(up.err, "did not create it")) << up.err;
    EXPECT_TRUE(NetnsExists(foreign));
    for (const RobotPlan& robot : test.scenario.robots) EXPECT_FALSE(NetnsExists(robot.netns));
    EXPECT_FALSE(StateExists(test.scenario.name));
  }
  // A device of the host's namespace named like a root-side veth is in another namespace than
  // ours: up goes on, and down leaves it.
  const std::string host_device = test.scenario.robots[0].root_veth;
  ASSERT_EQ(RunCommand({"ip", "tuntap", "add", "dev", host_device, "mode", "tap"}).exit_code, 0);
  CommandGuard link_guard({"ip", "tuntap", "del", "dev", host_device, "mode", "tap"});
  const CommandResult up = RunCommand({SitlnetBinary(), "up", test.path});
  EXPECT_EQ(up.exit_code, 0) << up.err;
  EXPECT_TRUE(LinkExistsInCtl(test.scenario.name, host_device));
  EXPECT_EQ(RunCommand({SitlnetBinary(), "down", test.scenario.name}).exit_code, 0);
  EXPECT_TRUE(LinkExistsInRoot(host_device));
}

TEST(NnsRefusalTest, BadScenarioFileIsUsageError) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();  // up checks privileges before it reads the file.
  const std::string path = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                           "/nns_bad_" + std::to_string(getpid()) + ".textproto";
  std::ofstream(path) << "name: \"bad\"\nrobot { nme: \"x\" }\n";
  const CommandResult up = RunCommand({SitlnetBinary(), "up", path});
  EXPECT_EQ(up.exit_code, 2);
  EXPECT_TRUE(Contains(up.err, path + ":2:")) << up.err;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace sitlnet::nns::testing

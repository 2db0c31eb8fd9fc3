// The sitlnet CLI end to end: exec passes status and environment, status
// shows what runs, kill -9 of `up` mid-way then `down` leaves nothing.
#include <linux/capability.h>
#include <sched.h>
#include <signal.h>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

bool Contains(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

TEST(NnsCliTest, ExecPassesExitStatusAndEnvironment) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("exe", 0, 2);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  ASSERT_EQ(RunCommand({SitlnetBinary(), "up", test.path}).exit_code, 0);
  const RobotPlan& r2 = s.robots[1];
  const std::string expected = r2.name + " " + std::to_string(r2.index) + " " +
                               FormatIpv4(r2.ctl_root_address) + ":" +
                               std::to_string(s.spec.addresses().physics_port());
  // By namespace name, and by robot name scoped with --scenario.
  for (const std::vector<std::string>& who :
       {std::vector<std::string>{r2.netns}, std::vector<std::string>{"--scenario", s.name, "r2"}}) {
    std::vector<std::string> argv = {SitlnetBinary(), "exec"};
    argv.insert(argv.end(), who.begin(), who.end());
    argv.insert(argv.end(), {"--", "sh", "-c",
                             "echo $SITLNET_ROBOT $SITLNET_ROBOT_INDEX $SITLNET_PHYSICS_ADDR; "
                             "exit 42"});
    const CommandResult result = RunCommand(argv);
    EXPECT_EQ(result.exit_code, 42) << result.err;
    EXPECT_EQ(result.out, expected + "\n");
  }
  // It really runs inside: the robot's own wlan0 address is there.
  const CommandResult ip = RunCommand(
      {SitlnetBinary(), "exec", r2.netns, "--", "ip", "-o", "-4", "addr", "show", "wlan0"});
  EXPECT_TRUE(Contains(ip.out, FormatIpv4(r2.wlan_address))) << ip.out << ip.err;
  // And it reaches the physics side of its own ctl0 with ping, also without CAP_NET_RAW (an
  // ICMP datagram socket: up allows them in every robot namespace).
  const CommandResult ping =
      RunCommand({SitlnetBinary(), "exec", r2.netns, "--", PingProgram(), "-n", "-c", "1", "-W",
                  "5", FormatIpv4(r2.ctl_root_address)});
  EXPECT_EQ(ping.exit_code, 0) << ping.out << ping.err;
  // Errors of exec itself: 127 not found, 125 unknown robot.
  EXPECT_EQ(RunCommand({SitlnetBinary(), "exec", r2.netns, "--", "/nonexistent/program"}).exit_code,
            127);
  const CommandResult unknown =
      RunCommand({SitlnetBinary(), "exec", "--scenario", s.name, "nobody", "--", "true"});
  EXPECT_EQ(unknown.exit_code, 125);
  EXPECT_TRUE(Contains(unknown.err, "no robot \"nobody\"")) << unknown.err;
}

TEST(NnsCliTest, StatusShowsRobotsDevicesAndProcesses) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("sta", 1, 2);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  ASSERT_EQ(RunCommand({SitlnetBinary(), "up", test.path}).exit_code, 0);
  Child sleeper({SitlnetBinary(), "exec", s.robots[0].netns, "--", "sh", "-c",
                 "echo ready; exec sleep 1000"});
  ASSERT_TRUE(sleeper.WaitForOutput(false, "ready", 10 * kNsPerS)) << sleeper.err();
  // "ready" comes from sh just before it execs sleep (same pid): wait for the exec to land.
  const std::string comm = "/proc/" + std::to_string(sleeper.pid()) + "/comm";
  const TimeNs deadline = MonotonicNowNs() + 10 * kNsPerS;
  while (ReadAll(comm) != "sleep\n" && MonotonicNowNs() < deadline) sched_yield();
  const CommandResult status = RunCommand({SitlnetBinary(), "status", s.name});
  EXPECT_EQ(status.exit_code, 0) << status.err;
  for (const RobotPlan& robot : s.robots) {
    EXPECT_TRUE(Contains(status.out, "robot " + robot.name)) << status.out;
    EXPECT_TRUE(Contains(status.out, FormatMac(robot.wlan_mac))) << status.out;
    EXPECT_TRUE(Contains(status.out, FormatIpv4(robot.ctl_robot_address) + "/30")) << status.out;
  }
  EXPECT_TRUE(Contains(status.out, std::to_string(sleeper.pid()) + ":sleep")) << status.out;
  EXPECT_EQ(RunCommand({SitlnetBinary(), "status", "nosuchscn"}).exit_code, 1);
  EXPECT_EQ(RunCommand({SitlnetBinary(), "down", s.name}).exit_code, 0);
  EXPECT_EQ(sleeper.Wait(5 * kNsPerS), 128 + SIGTERM);
}

TEST(NnsCliTest, KillDashNineOfUpMidWayThenDownLeavesNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("k9", 2, 8);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  {
    // The test hook holds `up` after robot 3 (docs/nns.md), a known mid-way.
    Child up({SitlnetBinary(), "up", test.path}, {"SITLNET_TEST_HOLD_AFTER_ROBOTS=3"});
    ASSERT_TRUE(up.WaitForOutput(true, "holding after robot 3", 20 * kNsPerS)) << up.err();
    ASSERT_EQ(kill(up.pid(), SIGKILL), 0);
    EXPECT_EQ(up.Wait(5 * kNsPerS), 128 + SIGKILL);
  }
  int left_behind = 0;
  for (const RobotPlan& robot : s.robots) left_behind += NetnsExists(robot.netns);
  EXPECT_GE(left_behind, 3);  // kill -9 left namespaces behind...
  EXPECT_LT(left_behind, 8);  // ...of an unfinished up.
  const CommandResult down = RunCommand({SitlnetBinary(), "down", s.name});
  EXPECT_EQ(down.exit_code, 0) << down.err;
  for (const RobotPlan& robot : s.robots) {
    EXPECT_FALSE(NetnsExists(robot.netns)) << robot.netns;
  }
  EXPECT_FALSE(NetnsExists(CtlNetnsName(s.name))) << s.name;  // The root sides went with it.
  EXPECT_FALSE(StateExists(s.name));
}

TEST(NnsCliTest, DownAllRemovesEveryScenario) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  // Other scenarios (another user's) would be removed too: only run when
  // nothing else is up, so the test never touches what it did not create.
  if (!ListScenarios().empty()) GTEST_SKIP() << "other scenarios are up; not running down --all";
  const TestScenario a = MakeScenario("ala", 3, 1);
  const TestScenario b = MakeScenario("alb", 4, 1);
  DownGuard guard_a(a.scenario.name);
  DownGuard guard_b(b.scenario.name);
  ASSERT_EQ(RunCommand({SitlnetBinary(), "up", a.path}).exit_code, 0);
  ASSERT_EQ(RunCommand({SitlnetBinary(), "up", b.path}).exit_code, 0);
  EXPECT_EQ(RunCommand({SitlnetBinary(), "down", "--all"}).exit_code, 0);
  EXPECT_TRUE(ListScenarios().empty());
  EXPECT_FALSE(NetnsExists(a.scenario.robots[0].netns));
  EXPECT_FALSE(NetnsExists(b.scenario.robots[0].netns));
}

TEST(NnsCliTest, EveryCommandHasHelp) {
  for (const char* command : {"up", "down", "exec", "status"}) {
    const CommandResult help = RunCommand({SitlnetBinary(), command, "--help"});
    EXPECT_EQ(help.exit_code, 0) << command;
    EXPECT_TRUE(Contains(help.out, std::string("usage: sitlnet ") + command)) << help.out;
    EXPECT_TRUE(Contains(help.out, "exit codes")) << help.out;
  }
  EXPECT_EQ(RunCommand({SitlnetBinary(), "frobnicate"}).exit_code, 2);
  EXPECT_EQ(RunCommand({SitlnetBinary(), "up"}).exit_code, 2);
}

}  // namespace
}  // namespace sitlnet::nns::testing

// physics_mujoco over the real ctl0 veths of an `up` scenario (issue 5): the native protocol
// round trip, isolation between robots, and a robot process that hovers a quad with the
// client library. Needs root (namespaces): skips without it, fails under CI=true.
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>

#include "nns/nns.h"
#include "physics_mujoco/client/physics_client.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/udp_socket.h"
#include "tests/integration/nns_test_util.h"

namespace sitlnet::physics {
namespace {

using nns::testing::Child;
using nns::testing::DownGuard;
using nns::testing::SitlnetBinary;
using physics_client::PhysicsClient;

// A scenario unique to this process and `slot` (0..4): name "ph<pid base 36><slot>", subnets
// 10.{220+slot}.<pid%250>.0/24 (ctl) and 10.{225+slot}.<pid%250>.0/24 (wlan), away from the
// defaults and from the nns tests' ranges. The file is removed on destruction.
struct PhysicsScenario {
  PhysicsScenario(int slot, const std::string& robots_text) {
    const unsigned pid = static_cast<unsigned>(getpid());
    std::string base36;
    for (unsigned v = pid; v != 0 || base36.empty(); v /= 36) {
      base36.insert(base36.begin(), "0123456789abcdefghijklmnopqrstuvwxyz"[v % 36]);
    }
    const std::string name = "ph" + base36 + std::to_string(slot);
    const std::string third = std::to_string(pid % 250);
    const std::string text = "name: \"" + name + "\"\n" + robots_text +
                             "addresses { ctl_subnet: \"10." + std::to_string(220 + slot) + "." +
                             third + ".0/24\" wlan_subnet: \"10." + std::to_string(225 + slot) +
                             "." + third + ".0/24\" }\n";
    const char* tmp = std::getenv("TMPDIR");
    path = std::string(tmp ? tmp : "/tmp") + "/" + name + ".textproto";
    std::ofstream(path) << text;
    scenario = LoadScenarioFile(path);
  }
  ~PhysicsScenario() { std::remove(path.c_str()); }
  std::string path;
  Scenario scenario;
};

// The server as runs make it: its sockets in the scenario's ctl namespace.
PhysicsServer ServerInCtlNamespace(const Scenario& scenario) {
  ServerOptions options;
  options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario.name));
  return PhysicsServer(scenario, options);
}

std::string ServerAddress(const Scenario& scenario, int robot) {
  return FormatIpv4(scenario.robots[robot].ctl_root_address) + ":" +
         std::to_string(scenario.spec.addresses().physics_port());
}

// Round-trip text of a double (std::to_string keeps 6 decimals: 3.16e-6 would become 3e-6).
std::string Exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// physics_hover_robot, built next to this test binary (<build>/tests/).
std::string HoverRobotBinary() {
  char self[4096] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  const std::string path(self, n > 0 ? n : 0);
  return path.substr(0, path.rfind('/')) + "/physics_hover_robot";
}

// Handles packets until `done` or 5 s (waits on the server's fd, no sleeps).
template <typename Done>
void PollUntil(PhysicsServer* server, Done done) {
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (!done() && MonotonicNowNs() < deadline) {
    pollfd fd{server->wait_fd(), POLLIN, 0};
    if (poll(&fd, 1, 100) > 0) server->Poll();
  }
}

TEST(PhysicsCtl0Test, ProtocolRoundTripThroughCtl0AndIsolation) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  PhysicsScenario t(0,
                    "robot { name: \"r1\" position_m { z: 5 } }\n"
                    "robot { name: \"r2\" position_m { x: 4 z: 5 } }\n");
  const Scenario& scenario = t.scenario;
  DownGuard down(scenario.name);
  nns::Up(scenario);
  PhysicsServer server = ServerInCtlNamespace(scenario);

  // The client's socket is created inside r1's namespace and stays bound to it.
  std::optional<PhysicsClient> client;
  {
    nns::ScopedNetns inside(scenario.robots[0].netns);
    client.emplace(ServerAddress(scenario, 0));
  }
  client->set_robot_index(0);
  ASSERT_TRUE(client->SendRotorSpeeds({1000, 1000, 1000, 1000}, 7));
  PollUntil(&server, [&] { return server.counters(0).commands_accepted == 1; });
  ASSERT_EQ(server.counters(0).commands_accepted, 1u);
  server.Advance(10);
  proto::RobotState state;
  ASSERT_TRUE(client->Receive(&state, 2000));
  EXPECT_EQ(state.robot(), 0u);
  EXPECT_EQ(state.command_step(), 7u);
  EXPECT_EQ(state.sim_time_ns(), 10 * kNsPerMs);
  EXPECT_EQ(state.position_m().z(), server.world().Pose(0).position_m.z);

  // From the ctl namespace itself the source is not r1's ctl0 address: dropped and counted.
  UdpSocket root = [&] {
    nns::ScopedNetns in_ctl(nns::CtlNetnsName(scenario.name));
    return UdpSocket::Bind(Ipv4{0}, 0, false, "test");
  }();
  const std::string bytes = [] {
    proto::MotorCommand command;
    for (int i = 0; i < 4; ++i) command.add_rotor_speed_rad_s(10);
    return command.SerializeAsString();
  }();
  ASSERT_TRUE(root.SendTo(
      bytes.data(), bytes.size(),
      MakeSockaddr(scenario.robots[0].ctl_root_address, scenario.spec.addresses().physics_port())));
  PollUntil(&server, [&] { return server.counters(0).dropped_foreign_source == 1; });
  EXPECT_EQ(server.counters(0).dropped_foreign_source, 1u);
  EXPECT_EQ(server.world().rotor_target(0)[0], 1000);

  // r2 has no route to r1's server: one robot can never drive another.
  {
    nns::ScopedNetns inside(scenario.robots[1].netns);
    UdpSocket r2 = UdpSocket::Bind(Ipv4{0}, 0, false, "test r2");
    EXPECT_FALSE(r2.SendTo(bytes.data(), bytes.size(),
                           MakeSockaddr(scenario.robots[0].ctl_root_address,
                                        scenario.spec.addresses().physics_port())));
  }
}

// Audit finding 10: anyone may bind an address that is not (yet) there (IP_FREEBIND needs no
// privilege), so a local user could take a robot's physics port on the host before the run and
// the server failed at start ("Address already in use"). The server's sockets are in the
// scenario's ctl namespace now, which only root can enter: the port held in the host's namespace
// stops nothing, and the robot's commands reach the server.
TEST(PhysicsCtl0Test, APhysicsPortTakenFirstInTheHostsNamespaceStopsNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  PhysicsScenario t(2, "robot { name: \"r1\" position_m { z: 5 } ardupilot_json_port: 9002 }\n");
  const Scenario& scenario = t.scenario;
  const RobotPlan& r1 = scenario.robots[0];
  const uint16_t port = static_cast<uint16_t>(scenario.spec.addresses().physics_port());
  UdpSocket squatter = UdpSocket::Bind(r1.ctl_root_address, port, true, "squatter");
  UdpSocket json_squatter = UdpSocket::Bind(r1.ctl_root_address, 9002, true, "squatter");
  DownGuard down(scenario.name);
  nns::Up(scenario);
  PhysicsServer server = ServerInCtlNamespace(scenario);
  std::optional<PhysicsClient> client;
  {
    nns::ScopedNetns inside(r1.netns);
    client.emplace(ServerAddress(scenario, 0));
  }
  client->set_robot_index(0);
  ASSERT_TRUE(client->SendRotorSpeeds({900, 900, 900, 900}, 1));
  PollUntil(&server, [&] { return server.counters(0).commands_accepted == 1; });
  EXPECT_EQ(server.counters(0).commands_accepted, 1u);
  EXPECT_EQ(server.world().rotor_target(0)[0], 900);
}

TEST(PhysicsCtl0Test, RobotProcessInANamespaceHoversAQuadWithTheClientLibrary) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  // On the ground (collision box half height 0.035 m), climbs to 1 m and holds it.
  PhysicsScenario t(1, "robot { name: \"r1\" position_m { z: 0.035 } }\n");
  const Scenario& scenario = t.scenario;
  DownGuard down(scenario.name);
  nns::Up(scenario);
  PhysicsServer server = ServerInCtlNamespace(scenario);
  const proto::Airframe& airframe = scenario.robots[0].airframe;
  const double duration_s = 8;
  // A separate process in r1's namespace, started the way users start robot software.
  Child robot({SitlnetBinary(), "exec", "--scenario", scenario.name, "r1", "--", HoverRobotBinary(),
               "--mass", Exact(airframe.mass_kg()), "--kf", Exact(airframe.thrust_coefficient()),
               "--max", Exact(airframe.max_rotor_speed_rad_s()), "--target-z", "1", "--duration-s",
               Exact(duration_s)});
  RunRealtime(&server, 1.0, static_cast<TimeNs>((duration_s + 0.05) * kNsPerS), -1);
  const int code = robot.Wait(10 * kNsPerS);
  ASSERT_EQ(code, 0) << robot.err();
  double max_dev_m = 1e9, final_z_m = 0;
  int states = 0;
  ASSERT_EQ(std::sscanf(robot.out().c_str(), "max_dev_m=%lf final_z_m=%lf states=%d", &max_dev_m,
                        &final_z_m, &states),
            3)
      << robot.out();
  std::printf("robot: %s", robot.out().c_str());
  // 100 Hz states for 8 s; a few may be lost to scheduling, most arrive.
  EXPECT_GT(states, 700);
  EXPECT_LT(max_dev_m, 0.05);
  EXPECT_NEAR(server.world().Pose(0).position_m.z, 1.0, 0.05);
  EXPECT_GT(server.counters(0).commands_accepted, 700u);
  EXPECT_EQ(server.counters(0).failsafe_cuts, 0u);
}

}  // namespace
}  // namespace sitlnet::physics

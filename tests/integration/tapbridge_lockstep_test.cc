// The library's lockstep driver with real TAPs (what the coordinator uses),
// and IPv6 through the daemon.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"
#include "tests/integration/tapbridge_test_util.h"

namespace sitlnet::tapbridge::testing {
namespace {

// A UDP socket bound to `address`:47000 inside namespace `netns` (created by this thread after
// setns; the socket stays there). In a lockstep scenario every robot has PERMANENT neighbour
// entries for its peers (docs/nns.md), so each datagram to a peer leaves as one frame on wlan0,
// queued on the TAP when send() returns, as a program's would, without ARP. Plain UDP needs no
// capability (a packet socket would need CAP_NET_RAW).
constexpr uint16_t kPort = 47000;

sockaddr_in SocketAddress(Ipv4 address) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_addr.s_addr = htonl(address.host_order);
  sa.sin_port = htons(kPort);
  return sa;
}

int UdpSocketIn(const std::string& netns, Ipv4 address) {
  const int original = open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
  const int target = open(("/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC);
  SITLNET_DEMAND(original >= 0 && target >= 0 && setns(target, CLONE_NEWNET) == 0);
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  const sockaddr_in local = SocketAddress(address);
  const int bound = bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof local);
  SITLNET_DEMAND(setns(original, CLONE_NEWNET) == 0);
  close(original);
  close(target);
  EXPECT_EQ(bound, 0) << "bind " << FormatIpv4(address) << " in " << netns << ": "
                      << std::strerror(errno);
  return fd;
}

bool SendTo(int fd, Ipv4 to, uint8_t tag) {
  const std::vector<uint8_t> payload(158, tag);  // 200-byte Ethernet frames.
  const sockaddr_in address = SocketAddress(to);
  return sendto(fd, payload.data(), payload.size(), 0, reinterpret_cast<const sockaddr*>(&address),
                sizeof address) == static_cast<ssize_t>(payload.size());
}

// Waits until wlan0 of `netns` is operational after the bridge attached its TAP. Attaching
// turns the carrier on, but the kernel swaps the drop-everything noop qdisc for the real one
// later, in its linkwatch work (net/core/link_watch.c: operstate, then dev_activate): a frame
// sent before that is dropped. `ip` observes the operstate (`state UP`); the qdisc follows
// within the same work item.
bool WaitUntilOperational(const std::string& netns) {
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (MonotonicNowNs() < deadline) {
    const CommandResult link =
        RunCommand({"ip", "-n", netns, "-o", "link", "show", "dev", "wlan0"});
    if (link.out.find("state UP") != std::string::npos) return true;
  }
  return false;
}

// Runs one lockstep step in which each robot sent three frames to the other;
// returns the delivery instants, in order.
std::vector<TimeNs> LockstepDeliveries(const Scenario& scenario, uint64_t seed,
                                       int* received_by_b) {
  BridgeOptions options;
  options.seed = seed;
  BridgeCore core(scenario, MakeMacPhySimMedium(scenario), options);
  core.AttachAll();
  std::vector<TimeNs> instants;
  core.AddDeliveryObserver([&](const Delivery& d) { instants.push_back(d.delivery_ns); });
  const RobotPlan& robot_a = scenario.robots[0];
  const RobotPlan& robot_b = scenario.robots[1];
  EXPECT_TRUE(WaitUntilOperational(robot_a.netns) && WaitUntilOperational(robot_b.netns));
  const int a = UdpSocketIn(robot_a.netns, robot_a.wlan_address);
  const int b = UdpSocketIn(robot_b.netns, robot_b.wlan_address);
  for (uint8_t k = 1; k <= 3; ++k) {
    EXPECT_TRUE(SendTo(a, robot_b.wlan_address, k)) << std::strerror(errno);
    EXPECT_TRUE(SendTo(b, robot_a.wlan_address, k)) << std::strerror(errno);
  }
  // send() has queued the frame on the TAP when it returns: the step sees all six.
  core.StepLockstep(10 * kNsPerMs);
  *received_by_b = 0;
  uint8_t buffer[2048];
  pollfd p{b, POLLIN, 0};
  while (*received_by_b < 3 && poll(&p, 1, 2000) == 1) {
    if (recv(b, buffer, sizeof buffer, MSG_DONTWAIT) > 0) ++*received_by_b;
  }
  close(a);
  close(b);
  return instants;
}

TEST(TapbridgeLockstep, DeliveriesWrittenWithinTheStepAndReproducible) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario up("lck", 2,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                    "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n"
                    "timing { pacing: PACING_LOCKSTEP }\n");
  const Scenario scenario = LoadScenarioFile(up.path());
  int received = 0;
  const std::vector<TimeNs> first = LockstepDeliveries(scenario, 7, &received);
  EXPECT_EQ(received, 3) << "b's frames written before StepLockstep returned";
  ASSERT_EQ(first.size(), 6u);
  for (TimeNs t : first) EXPECT_LE(t, 10 * kNsPerMs);
  const std::vector<TimeNs> again = LockstepDeliveries(scenario, 7, &received);
  EXPECT_EQ(first, again) << "same seed, same frames: same delivery instants";
  const std::vector<TimeNs> other = LockstepDeliveries(scenario, 8, &received);
  EXPECT_NE(first, other) << "the seed places the frames within the step";
}

// Audit finding 16: a robot cannot hold the bridge by writing frames as fast as it reads them.
// Robot a queues 1000 frames on its TAP and b three before one step: the step reads at most the
// budget (256) from a, and b's three all the same; a's rest waits in its TAP's queue (none lost)
// and is read in the steps that follow.
TEST(TapbridgeLockstep, AFloodingRobotIsReadAtMostTheBudgetPerStep) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario up("fld", 2,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                    "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n"
                    "timing { pacing: PACING_LOCKSTEP }\n");
  const Scenario scenario = LoadScenarioFile(up.path());
  BridgeCore core(scenario, MakeMacPhySimMedium(scenario), BridgeOptions{});
  core.AttachAll();
  const RobotPlan& robot_a = scenario.robots[0];
  const RobotPlan& robot_b = scenario.robots[1];
  ASSERT_TRUE(WaitUntilOperational(robot_a.netns) && WaitUntilOperational(robot_b.netns));
  const int a = UdpSocketIn(robot_a.netns, robot_a.wlan_address);
  const int b = UdpSocketIn(robot_b.netns, robot_b.wlan_address);
  constexpr int kFlood = 1000;
  for (int k = 0; k < kFlood; ++k) {
    ASSERT_TRUE(SendTo(a, robot_b.wlan_address, 1)) << k << ": " << std::strerror(errno);
  }
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(SendTo(b, robot_a.wlan_address, 2));
  core.StepLockstep(10 * kNsPerMs);
  EXPECT_EQ(core.port_counters(0).frames_read, 256u);
  EXPECT_EQ(core.port_counters(1).frames_read, 3u);
  for (TimeNs until_ms = 20; until_ms <= 40; until_ms += 10) core.StepLockstep(until_ms * kNsPerMs);
  EXPECT_EQ(core.port_counters(0).frames_read, static_cast<uint64_t>(kFlood));
  close(a);
  close(b);
}

// IPv6 link-local unicast and all-nodes multicast cross the medium.
TEST(TapbridgeTraffic, Ipv6LinkLocalUnicastAndMulticast) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("ip6", 3,
                          "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                          "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n",
                          "ipv6: IPV6_LINK_LOCAL");
  scenario.StartDaemon();
  // b's link-local address from its MAC 02:00:00:00:00:01 (EUI-64, U/L bit
  // flipped). -w: ping retries until 2 replies while DAD completes.
  const CommandResult unicast =
      scenario.Exec("a", {PingProgram(), "-6", "-c", "2", "-w", "10", "fe80::ff:fe00:1%wlan0"});
  EXPECT_EQ(unicast.exit_code, 0) << unicast.out << unicast.err;
  const CommandResult multicast =
      scenario.Exec("a", {PingProgram(), "-6", "-c", "2", "-w", "10", "ff02::1%wlan0"});
  EXPECT_NE(multicast.out.find("from fe80::ff:fe00:1"), std::string::npos) << multicast.out;
}

}  // namespace
}  // namespace sitlnet::tapbridge::testing

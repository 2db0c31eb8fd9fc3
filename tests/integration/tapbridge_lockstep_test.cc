// The library's lockstep driver with real TAPs (what the coordinator uses),
// and IPv6 through the daemon.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/if_packet.h>
#include <net/if.h>
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

// An AF_PACKET socket on wlan0 of namespace `netns`: frames sent on it enter
// the robot's TAP exactly like a program's frames.
int PacketSocket(const std::string& netns) {
  const int original = open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
  const int target = open(("/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC);
  SITLNET_DEMAND(original >= 0 && target >= 0 && setns(target, CLONE_NEWNET) == 0);
  const int fd = socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC, htons(0x88b5));
  sockaddr_ll address{};
  address.sll_family = AF_PACKET;
  address.sll_protocol = htons(0x88b5);
  address.sll_ifindex = static_cast<int>(if_nametoindex("wlan0"));
  SITLNET_DEMAND(bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  SITLNET_DEMAND(setns(original, CLONE_NEWNET) == 0);
  close(original);
  close(target);
  return fd;
}

std::vector<uint8_t> Frame(int from, int to, uint8_t tag) {
  std::vector<uint8_t> frame(200, tag);
  std::memcpy(frame.data(), RobotMac(to).bytes.data(), 6);
  std::memcpy(frame.data() + 6, RobotMac(from).bytes.data(), 6);
  frame[12] = 0x88;  // Local experimental ethertype.
  frame[13] = 0xb5;
  return frame;
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
  core.AddDeliveryObserver([&](const Delivery& d) { instants.push_back(d.time_ns); });
  const int a = PacketSocket(scenario.robots[0].netns);
  const int b = PacketSocket(scenario.robots[1].netns);
  for (uint8_t k = 1; k <= 3; ++k) {
    const std::vector<uint8_t> ab = Frame(0, 1, k), ba = Frame(1, 0, k);
    EXPECT_EQ(send(a, ab.data(), ab.size(), 0), static_cast<ssize_t>(ab.size()));
    EXPECT_EQ(send(b, ba.data(), ba.size(), 0), static_cast<ssize_t>(ba.size()));
  }
  // send() on a packet socket has queued the frame on the TAP when it
  // returns: the step sees all six.
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
                    "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n");
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
  const Result unicast =
      scenario.Exec("a", {"ping", "-6", "-c", "2", "-w", "10", "fe80::ff:fe00:1%wlan0"});
  EXPECT_EQ(unicast.code, 0) << unicast.out << unicast.err;
  const Result multicast =
      scenario.Exec("a", {"ping", "-6", "-c", "2", "-w", "10", "ff02::1%wlan0"});
  EXPECT_NE(multicast.out.find("from fe80::ff:fe00:1"), std::string::npos) << multicast.out;
}

}  // namespace
}  // namespace sitlnet::tapbridge::testing

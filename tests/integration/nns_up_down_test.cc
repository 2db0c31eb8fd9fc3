// `up` creates exactly the devices docs/nns.md specifies, isolated as
// specified, and `down` leaves nothing. Observed with `ip`, ping and tcpdump,
// independent of the library's own netlink code.
#include <linux/capability.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

bool Contains(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

// `ip -n NETNS -o ARGS...` (one line per object).
CommandResult IpIn(const std::string& netns, std::vector<std::string> args) {
  std::vector<std::string> argv = {"ip", "-n", netns, "-o"};
  argv.insert(argv.end(), args.begin(), args.end());
  return RunCommand(argv);
}

std::string ReadFileText(const std::string& path) {
  std::ifstream file(path);
  std::string text;
  std::getline(file, text);
  return text;
}

TEST(NnsUpTest, ThreeRobotsHaveTheSpecifiedDevicesAddressesAndRoutes) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("dev", 0, 3);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  Up(s);
  for (const RobotPlan& robot : s.robots) {
    SCOPED_TRACE(robot.netns);
    // Named namespace, usable by iproute2.
    EXPECT_TRUE(Contains(RunCommand({"ip", "netns", "list"}).out, robot.netns));

    const std::string lo = IpIn(robot.netns, {"link", "show", "dev", "lo"}).out;
    EXPECT_TRUE(Contains(lo, ",UP")) << lo;

    // wlan0: persistent TAP without packet info, robot MAC, txqueuelen,
    // addrgenmode none (silent IPv6 is the default), administratively up.
    const std::string wlan = IpIn(robot.netns, {"-d", "link", "show", "dev", "wlan0"}).out;
    EXPECT_TRUE(Contains(wlan, "tun type tap pi off vnet_hdr off persist on")) << wlan;
    EXPECT_TRUE(Contains(wlan, "link/ether " + FormatMac(RobotMac(robot.index)))) << wlan;
    EXPECT_TRUE(Contains(wlan, "qlen " + std::to_string(s.spec.addresses().txqueuelen()))) << wlan;
    EXPECT_TRUE(Contains(wlan, "addrgenmode none")) << wlan;
    EXPECT_TRUE(Contains(wlan, ",UP")) << wlan;
    const std::string wlan_addr = IpIn(robot.netns, {"-4", "addr", "show", "dev", "wlan0"}).out;
    EXPECT_TRUE(Contains(wlan_addr, "inet " + FormatIpv4(robot.wlan_address) + "/" +
                                        std::to_string(s.wlan_subnet.length)))
        << wlan_addr;

    // ctl0: veth, /30 robot side, no multicast, silent IPv6, up.
    const std::string ctl = IpIn(robot.netns, {"-d", "link", "show", "dev", "ctl0"}).out;
    EXPECT_TRUE(Contains(ctl, " veth ")) << ctl;
    EXPECT_FALSE(Contains(ctl, "MULTICAST")) << ctl;
    EXPECT_TRUE(Contains(ctl, "addrgenmode none")) << ctl;
    EXPECT_TRUE(Contains(ctl, ",UP")) << ctl;
    const std::string ctl_addr = IpIn(robot.netns, {"-4", "addr", "show", "dev", "ctl0"}).out;
    EXPECT_TRUE(Contains(ctl_addr, "inet " + FormatIpv4(robot.ctl_robot_address) + "/30"))
        << ctl_addr;
    // No IPv6 address at all on wlan0 and ctl0 (no link-local: no chatter).
    EXPECT_EQ(IpIn(robot.netns, {"-6", "addr", "show", "dev", "wlan0"}).out, "");
    EXPECT_EQ(IpIn(robot.netns, {"-6", "addr", "show", "dev", "ctl0"}).out, "");
    // Exactly three devices.
    const std::string links = IpIn(robot.netns, {"link", "show"}).out;
    EXPECT_EQ(std::count(links.begin(), links.end(), '\n'), 3) << links;

    // Realtime pacing (the default): ARP as usual, no static entries.
    EXPECT_EQ(RunCommand({"ip", "-n", robot.netns, "neigh", "show", "nud", "permanent"}).out, "");

    // Routes: the two connected prefixes, and no default route.
    const std::string routes = RunCommand({"ip", "-n", robot.netns, "-4", "route", "show"}).out;
    EXPECT_FALSE(Contains(routes, "default")) << routes;
    EXPECT_EQ(std::count(routes.begin(), routes.end(), '\n'), 2) << routes;
    EXPECT_TRUE(Contains(routes, FormatIpv4Prefix(s.wlan_subnet) + " dev wlan0")) << routes;

    // Root side: the veth by its planned name in the scenario's ctl namespace, not the host's,
    // its /30 address, forwarding and proxy_arp off on that interface.
    const std::string ctl_netns = CtlNetnsName(s.name);
    const std::string root =
        RunCommand({"ip", "-n", ctl_netns, "-o", "-4", "addr", "show", "dev", robot.root_veth}).out;
    EXPECT_TRUE(Contains(root, "inet " + FormatIpv4(robot.ctl_root_address) + "/30")) << root;
    EXPECT_FALSE(LinkExistsInRoot(robot.root_veth)) << robot.root_veth;
    EXPECT_FALSE(Contains(RunCommand({"ip", "-o", "-4", "addr", "show"}).out,
                          "inet " + FormatIpv4(robot.ctl_root_address) + "/"));
    const std::string conf = "/proc/sys/net/ipv4/conf/" + robot.root_veth + "/";
    ScopedNetns in_ctl(ctl_netns);  // /proc/sys/net is the namespace of the thread that opens it.
    EXPECT_EQ(ReadFileText(conf + "forwarding"), "0");
    EXPECT_EQ(ReadFileText(conf + "proxy_arp"), "0");
  }
}

TEST(NnsUpTest, LinkLocalPolicyKeepsKernelIpv6Addresses) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("ll", 1, 1, "ipv6: IPV6_LINK_LOCAL");
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  const std::string netns = test.scenario.robots[0].netns;
  const std::string ctl = IpIn(netns, {"-d", "link", "show", "dev", "ctl0"}).out;
  EXPECT_FALSE(Contains(ctl, "addrgenmode none")) << ctl;
  // The veth has carrier, so the kernel gives it a link-local address at once.
  const std::string ctl6 = IpIn(netns, {"-6", "addr", "show", "dev", "ctl0"}).out;
  EXPECT_TRUE(Contains(ctl6, "inet6 fe80::")) << ctl6;
}

TEST(NnsUpTest, TheCtlNamespaceReachesEveryRobotOverCtl0) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("png", 2, 3);
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  for (const RobotPlan& robot : test.scenario.robots) {
    EXPECT_EQ(UdpRoundTrip(test.scenario.name, robot.netns, robot.ctl_robot_address), "")
        << robot.name;
    if (!HasCapability(CAP_NET_RAW)) continue;  // ping's raw socket needs it.
    const CommandResult ping =
        RunCommand({"ip", "netns", "exec", CtlNetnsName(test.scenario.name), "ping", "-n", "-c",
                    "1", "-W", "5", FormatIpv4(robot.ctl_robot_address)});
    EXPECT_EQ(ping.exit_code, 0) << robot.name << ": " << ping.out << ping.err;
  }
  if (!HasCapability(CAP_NET_RAW)) std::printf("(no CAP_NET_RAW: checked with UDP, not ping)\n");
}

// Every robot namespace allows ICMP datagram sockets to all groups (net.ipv4.ping_group_range
// "0 2147483647", as systemd sets on a host), so ping and robot software need no CAP_NET_RAW
// there; the root namespace keeps its own value. The kernel checks only the caller's group
// against the range when such a socket is created (net/ipv4/ping.c, ping_init_sock), not
// capabilities: creating one is the oracle, in either pass.
TEST(NnsUpTest, RobotNamespacesAllowPingWithoutCapNetRaw) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string range_path = "/proc/sys/net/ipv4/ping_group_range";
  const std::string root_before = ReadAll(range_path);
  const TestScenario test = MakeScenario("icm", 7, 2);
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  EXPECT_EQ(ReadAll(range_path), root_before) << "the root namespace's range is not ours";
  for (const RobotPlan& robot : test.scenario.robots) {
    const CommandResult range =
        RunCommand({SitlnetBinary(), "exec", robot.netns, "--", "cat", range_path});
    EXPECT_EQ(range.out, "0\t2147483647\n") << robot.name << ": " << range.err;
    int socket_error = 0;
    std::thread inside([&] {
      ScopedNetns enter(robot.netns);
      const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, IPPROTO_ICMP);
      socket_error = fd < 0 ? errno : 0;
      if (fd >= 0) close(fd);
    });
    inside.join();
    EXPECT_EQ(socket_error, 0) << robot.name
                               << ": ICMP datagram socket: " << std::strerror(socket_error);
  }
}

TEST(NnsUpTest, OutsideAddressIsUnreachableInsideARobot) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("rte", 3, 1);
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  // No default route: the lookup itself fails, so no packet can leave.
  const CommandResult get =
      RunCommand({"ip", "-n", test.scenario.robots[0].netns, "route", "get", "192.0.2.1"});
  EXPECT_NE(get.exit_code, 0) << get.out;
  EXPECT_TRUE(Contains(get.err, "Network is unreachable")) << get.err;
  // Another robot's ctl /30 is not reachable either (only its own /30 is).
  const TestScenario two = MakeScenario("rtf", 4, 2);
  DownGuard guard2(two.scenario.name);
  Up(two.scenario);
  const CommandResult peer = RunCommand({"ip", "-n", two.scenario.robots[0].netns, "route", "get",
                                         FormatIpv4(two.scenario.robots[1].ctl_robot_address)});
  EXPECT_NE(peer.exit_code, 0) << peer.out;
}

// Ethernet + ARP request layout (RFC 826): ethertype at 12, sender hardware
// address at 22, target protocol address at 38.
bool IsArpRequestFor(const uint8_t* frame, size_t length, const MacAddress& sender, Ipv4 target) {
  if (length < 42 || frame[12] != 0x08 || frame[13] != 0x06) return false;
  if (std::memcmp(frame + 6, sender.bytes.data(), 6) != 0) return false;
  if (std::memcmp(frame + 22, sender.bytes.data(), 6) != 0) return false;
  const uint8_t want[4] = {
      static_cast<uint8_t>(target.host_order >> 24), static_cast<uint8_t>(target.host_order >> 16),
      static_cast<uint8_t>(target.host_order >> 8), static_cast<uint8_t>(target.host_order)};
  return std::memcmp(frame + 38, want, 4) == 0;
}

TEST(NnsUpTest, PingInsideARobotReachesItsTapAndTcpdump) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("tap", 5, 3);
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  const RobotPlan& r1 = test.scenario.robots[0];
  const RobotPlan& r2 = test.scenario.robots[1];

  // Attaching gives the TAP carrier; frames are dropped before that.
  UniqueFd tap = AttachTap(r1.netns, "wlan0");
  // tcpdump needs CAP_NET_RAW for its packet socket; without it (the
  // capability-dropped run) the TAP alone is the observer.
  const bool raw = HasCapability(CAP_NET_RAW);
  std::unique_ptr<Child> tcpdump;
  if (raw) {
    tcpdump = std::make_unique<Child>(std::vector<std::string>{
        "ip", "netns", "exec", r1.netns, "tcpdump", "-n", "-l", "-i", "wlan0", "-c", "1", "arp"});
    ASSERT_TRUE(tcpdump->WaitForOutput(/*from_stderr=*/true, "listening on", 10 * kNsPerS))
        << tcpdump->err();
  }

  // r2 is on the wlan subnet, so r1 ARPs for it on wlan0. Nobody answers
  // (no medium here): ping fails, but its frames must have gone out.
  const std::string target = FormatIpv4(r2.wlan_address);
  Child sender(
      {"ip", "netns", "exec", r1.netns, PingProgram(), "-n", "-c", "1", "-W", "3", target});
  bool seen = false;
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (!seen && MonotonicNowNs() < deadline) {
    pollfd fd{tap.get(), POLLIN, 0};
    if (poll(&fd, 1, static_cast<int>((deadline - MonotonicNowNs()) / kNsPerMs) + 1) <= 0) break;
    uint8_t frame[2048];
    const ssize_t n = read(tap.get(), frame, sizeof frame);
    if (n > 0) seen = IsArpRequestFor(frame, n, r1.wlan_mac, r2.wlan_address);
  }
  EXPECT_TRUE(seen) << "no ARP request for " << FormatIpv4(r2.wlan_address) << " on the TAP";
  if (!raw) {
    std::printf("(no CAP_NET_RAW: tcpdump not run, the TAP alone observed the frame)\n");
    return;
  }
  EXPECT_EQ(tcpdump->Wait(10 * kNsPerS), 0) << tcpdump->err();
  EXPECT_TRUE(Contains(tcpdump->out(),
                       "Request who-has " + target + " tell " + FormatIpv4(r1.wlan_address)))
      << tcpdump->out();
}

TEST(NnsUpTest, LockstepScenarioHasPermanentNeighboursSoNoArpIsSent) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("lck", 6, 3, "", "timing { pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  const RobotPlan& r1 = test.scenario.robots[0];
  const RobotPlan& r3 = test.scenario.robots[2];
  const std::string neighbours =
      RunCommand({"ip", "-n", r1.netns, "-4", "neigh", "show", "dev", "wlan0"}).out;
  EXPECT_EQ(std::count(neighbours.begin(), neighbours.end(), '\n'), 2) << neighbours;
  for (const RobotPlan& peer : test.scenario.robots) {
    if (peer.index == r1.index) continue;
    EXPECT_TRUE(Contains(neighbours, FormatIpv4(peer.wlan_address) + " lladdr " +
                                         FormatMac(peer.wlan_mac) + " PERMANENT"))
        << neighbours;
  }
  // The first frame r1 sends to r3 is the datagram itself, to r3's MAC: no ARP.
  UniqueFd tap = AttachTap(r1.netns, "wlan0");
  Child sender({SitlnetBinary(), "exec", r1.netns, "--", "bash", "-c",
                "echo x > /dev/udp/" + FormatIpv4(r3.wlan_address) + "/9"});
  pollfd fd{tap.get(), POLLIN, 0};
  ASSERT_EQ(poll(&fd, 1, 5000), 1) << "nothing on the TAP";
  uint8_t frame[2048];
  const ssize_t n = read(tap.get(), frame, sizeof frame);
  ASSERT_GE(n, 34);
  EXPECT_EQ(std::memcmp(frame, r3.wlan_mac.bytes.data(), 6), 0) << "not addressed to r3's MAC";
  EXPECT_EQ(frame[12], 0x08);  // IPv4, not ARP (0x0806).
  EXPECT_EQ(frame[13], 0x00);
  EXPECT_EQ(sender.Wait(5 * kNsPerS), 0);
}

// A node host (issue 35) brings up its slice of a scenario's robots under their usual names, and
// `down` removes exactly that slice. Robots 0 and 2 of 3 here; robot 1's namespace name is held
// by a namespace the slice does not own (as another node's would be in a shared root).
TEST(NnsDownTest, ASliceOfRobotsComesUpAloneAndDownRemovesExactlyIt) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("slc", 5, 3);
  const Scenario& s = test.scenario;
  const std::string other = s.robots[1].netns;
  ASSERT_EQ(RunCommand({"ip", "netns", "add", other}).exit_code, 0);
  CommandGuard netns_guard({"ip", "netns", "del", other});
  DownGuard guard(s.name);
  UpOptions options;
  options.robots = {0, 2};
  Up(s, options);
  const std::optional<ScenarioState> state = ReadScenarioState(s.name);
  ASSERT_TRUE(state.has_value());
  ASSERT_EQ(state->robots.size(), 2u);
  EXPECT_EQ(state->robots[0].index, 0);
  EXPECT_EQ(state->robots[1].index, 2);
  for (const int index : {0, 2}) {
    const RobotPlan& robot = s.robots[index];
    EXPECT_TRUE(Contains(IpIn(robot.netns, {"link", "show", "dev", "wlan0"}).out, ",UP"))
        << robot.name;
    EXPECT_TRUE(LinkExistsInCtl(s.name, robot.root_veth)) << robot.root_veth;
    EXPECT_EQ(UdpRoundTrip(s.name, robot.netns, robot.ctl_robot_address), "") << robot.name;
  }
  EXPECT_FALSE(LinkExistsInCtl(s.name, s.robots[1].root_veth));
  // The namespace of robot 1 was not entered: it holds its loopback only.
  const std::string links = IpIn(other, {"link", "show"}).out;
  EXPECT_EQ(std::count(links.begin(), links.end(), '\n'), 1) << links;

  const DownReport report = Down(s.name);
  EXPECT_EQ(report.namespaces_removed, 3);  // Robots 0 and 2, and the ctl namespace.
  EXPECT_EQ(report.links_removed, 2);
  EXPECT_TRUE(NetnsExists(other));
  EXPECT_FALSE(NetnsExists(s.robots[0].netns));
  EXPECT_FALSE(NetnsExists(s.robots[2].netns));
  EXPECT_FALSE(NetnsExists(CtlNetnsName(s.name)));
  EXPECT_FALSE(StateExists(s.name));
}

TEST(NnsDownTest, DownLeavesNoNamespaceLinkProcessOrState) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("dwn", 6, 3);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  Up(s);
  // One process that exits on SIGTERM, one that ignores it (SIG_IGN survives
  // exec): down must escalate to SIGKILL. "ready" is printed inside.
  Child polite({SitlnetBinary(), "exec", s.robots[0].netns, "--", "sh", "-c",
                "echo ready; exec sleep 1000"});
  Child stubborn({SitlnetBinary(), "exec", s.robots[2].netns, "--", "sh", "-c",
                  "trap '' TERM; echo ready; exec sleep 1000"});
  ASSERT_TRUE(polite.WaitForOutput(false, "ready", 10 * kNsPerS)) << polite.err();
  ASSERT_TRUE(stubborn.WaitForOutput(false, "ready", 10 * kNsPerS)) << stubborn.err();

  const DownReport report = Down(s.name);
  EXPECT_EQ(report.namespaces_removed, 4);  // The robots' and the ctl namespace.
  EXPECT_FALSE(NetnsExists(CtlNetnsName(s.name)));
  EXPECT_EQ(report.links_removed, 3);
  EXPECT_EQ(report.processes_terminated, 1);
  EXPECT_EQ(report.processes_killed, 1);
  EXPECT_EQ(polite.Wait(5 * kNsPerS), 128 + SIGTERM);
  EXPECT_EQ(stubborn.Wait(5 * kNsPerS), 128 + SIGKILL);
  for (const RobotPlan& robot : s.robots) {
    EXPECT_FALSE(NetnsExists(robot.netns)) << robot.netns;
    EXPECT_FALSE(LinkExistsInRoot(robot.root_veth)) << robot.root_veth;
  }
  EXPECT_FALSE(Contains(RunCommand({"ip", "netns", "list"}).out, s.name + "-"));
  EXPECT_FALSE(StateExists(s.name));
  // Idempotent.
  const DownReport again = Down(s.name);
  EXPECT_EQ(again.namespaces_removed + again.links_removed, 0);
}

TEST(NnsDownTest, FailureHalfWayRollsBackEverything) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("rbk", 7, 5);
  const Scenario& s = test.scenario;
  DownGuard guard(s.name);
  UpOptions options;
  options.on_robot_done = [](int robots_done) {
    if (robots_done == 2) throw Error("injected failure after robot 2");
  };
  EXPECT_THROW(Up(s, options), Error);
  EXPECT_FALSE(NetnsExists(CtlNetnsName(s.name)));
  for (const RobotPlan& robot : s.robots) {
    EXPECT_FALSE(NetnsExists(robot.netns)) << robot.netns;
    EXPECT_FALSE(LinkExistsInRoot(robot.root_veth)) << robot.root_veth;
  }
  EXPECT_FALSE(StateExists(s.name));
}

TEST(NnsDownTest, TwoScenariosCoexistAndGoDownSeparately) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario a = MakeScenario("coa", 8, 2);
  const TestScenario b = MakeScenario("cob", 9, 2);
  DownGuard guard_a(a.scenario.name);
  DownGuard guard_b(b.scenario.name);
  Up(a.scenario);
  Up(b.scenario);
  const std::vector<std::string> names = ListScenarios();
  EXPECT_NE(std::find(names.begin(), names.end(), a.scenario.name), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), b.scenario.name), names.end());
  Down(a.scenario.name);
  for (const RobotPlan& robot : a.scenario.robots) EXPECT_FALSE(NetnsExists(robot.netns));
  for (const RobotPlan& robot : b.scenario.robots) {
    EXPECT_TRUE(NetnsExists(robot.netns));
    EXPECT_TRUE(LinkExistsInCtl(b.scenario.name, robot.root_veth));
    EXPECT_EQ(UdpRoundTrip(b.scenario.name, robot.netns, robot.ctl_robot_address), "")
        << robot.name;
  }
}

TEST(NnsDownTest, UpAgainReplacesOwnLeftovers) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const TestScenario test = MakeScenario("again", 0, 2);
  DownGuard guard(test.scenario.name);
  Up(test.scenario);
  Up(test.scenario);  // Leftovers are ours (state file): removed, recreated.
  for (const RobotPlan& robot : test.scenario.robots) {
    EXPECT_TRUE(NetnsExists(robot.netns));
    EXPECT_TRUE(LinkExistsInCtl(test.scenario.name, robot.root_veth));
  }
}

}  // namespace
}  // namespace sitlnet::nns::testing

// Captures and bad input: pcap read by tshark, live capture, oversize frames,
// a changed source MAC, TAP overflow, a namespace deleted under the daemon,
// daemon restart.
#include <gtest/gtest.h>
#include <linux/capability.h>
#include <signal.h>

#include <sstream>

#include "tests/integration/tapbridge_test_util.h"

namespace sitlnet::tapbridge::testing {
namespace {

const char* kTwo =
    "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
    "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n";

bool Pings(MediumScenario& s, const std::string& from, int to, int count = 2) {
  return s.Exec(from,
                {PingProgram(), "-c", std::to_string(count), "-W", "1", "-i", "0.2", s.Address(to)})
             .exit_code == 0;
}

int Lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

TEST(TapbridgeCapture, PcapFileDecodesCleanlyWithSignal) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("pcp", 0, kTwo);
  const std::string pcap = scenario.dir() + "/air.pcap";
  scenario.StartDaemon({"--pcap", pcap});
  ASSERT_TRUE(Pings(scenario, "a", 1, 5));
  scenario.StopDaemon();
  const CommandResult fields =
      RunCommand({"tshark", "-r", pcap, "-T", "fields", "-e", "radiotap.dbm_antsignal", "-e",
                  "radiotap.dbm_antnoise", "-e", "wlan.fc.type_subtype"});
  ASSERT_EQ(fields.exit_code, 0) << fields.err;
  std::istringstream lines(fields.out);
  std::string line;
  int frames = 0, acks = 0, data = 0;
  while (std::getline(lines, line)) {
    ++frames;
    std::istringstream f(line);
    std::string signal, noise, subtype;
    f >> signal >> noise >> subtype;
    EXPECT_FALSE(signal.empty() || noise.empty()) << "frame " << frames << ": " << line;
    if (subtype == "0x001d" || subtype == "29") ++acks;
    if (subtype == "0x0020" || subtype == "32") ++data;
  }
  EXPECT_GE(data, 10) << fields.out;  // 5 requests + 5 replies (+ ARP)
  EXPECT_GE(acks, 10) << fields.out;
  const CommandResult malformed = RunCommand({"tshark", "-r", pcap, "-Y", "_ws.malformed"});
  EXPECT_EQ(malformed.exit_code, 0);
  EXPECT_EQ(Lines(malformed.out), 0) << malformed.out;
  // Debian's tcpdump, run as root, switches to user tcpdump after opening the file (even with
  // -Z root it calls initgroups), which needs CAP_SETUID + CAP_SETGID: without them (the
  // min-caps pass) tshark above is the only decoder.
  if (!integration_test::HasCapability(CAP_SETUID) ||
      !integration_test::HasCapability(CAP_SETGID)) {
    std::printf("(no CAP_SETUID/CAP_SETGID: tcpdump -r not run, it would switch user)\n");
    return;
  }
  const CommandResult tcpdump = RunCommand({"tcpdump", "-r", pcap, "-n"});
  EXPECT_EQ(tcpdump.exit_code, 0) << tcpdump.err;
  EXPECT_GE(Lines(tcpdump.out), frames);
}

// Hidden terminals (line3: r1 and r3 cannot hear each other, both send to
// r2): their frames overlap at r2, so the pcap must show frames with the
// bad-FCS flag (collided at the addressed receiver) and retransmissions with
// the Retry bit, and still decode without malformed packets.
TEST(TapbridgeCapture, HiddenTerminalCollisionsShowBadFcsAndRetries) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("hid", 3,
                          "robot { name: \"r1\" position_m { x: 0 y: 0 z: 2 } }\n"
                          "robot { name: \"r2\" position_m { x: 45 y: 0 z: 2 } }\n"
                          "robot { name: \"r3\" position_m { x: 90 y: 0 z: 2 } }\n"
                          "radio { standard: STANDARD_80211A rate_mbps: 6 }\n");
  const std::string pcap = scenario.dir() + "/air.pcap";
  scenario.StartDaemon({"--pcap", pcap});
  ASSERT_TRUE(Pings(scenario, "r1", 1, 1));  // ARP resolved before the floods.
  ASSERT_TRUE(Pings(scenario, "r3", 1, 1));
  auto flood1 = scenario.Spawn(
      "r1", {PingProgram(), "-q", "-f", "-c", "500", "-s", "1000", scenario.Address(1)});
  auto flood3 = scenario.Spawn(
      "r3", {PingProgram(), "-q", "-f", "-c", "500", "-s", "1000", scenario.Address(1)});
  flood1->Wait(60 * kNsPerS);
  flood3->Wait(60 * kNsPerS);
  scenario.StopDaemon();
  const CommandResult bad = RunCommand({"tshark", "-r", pcap, "-Y", "radiotap.flags.badfcs == 1"});
  const CommandResult retries = RunCommand({"tshark", "-r", pcap, "-Y", "wlan.fc.retry == 1"});
  const CommandResult malformed = RunCommand({"tshark", "-r", pcap, "-Y", "_ws.malformed"});
  std::printf("hidden terminals: %d bad-FCS frames, %d retries in the pcap\n", Lines(bad.out),
              Lines(retries.out));
  EXPECT_GT(Lines(bad.out), 0);
  EXPECT_GT(Lines(retries.out), 0);
  EXPECT_EQ(Lines(malformed.out), 0) << malformed.out;
}

// `sitlnet capture --medium NAME | tshark -i -` while traffic flows.
TEST(TapbridgeCapture, LiveCaptureStreamsToTshark) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("liv", 1, kTwo);
  scenario.StartDaemon();
  Child capture({"sh", "-c",
                 SitlnetBinary() + " capture --medium " + scenario.name() +
                     " | tshark -l -i - -c 6 -T fields -e radiotap.dbm_antsignal"
                     " -e wlan.fc.type_subtype"});
  // Traffic until tshark has its 6 frames (bounded).
  for (int i = 0; i < 50 && capture.Poll() < 0; ++i) Pings(scenario, "a", 1, 1);
  ASSERT_EQ(capture.Wait(10 * kNsPerS), 0) << capture.err();
  EXPECT_EQ(Lines(capture.out()), 6) << capture.out();
  EXPECT_EQ(capture.out().find("\t\n"), std::string::npos);
}

// The robot's own view: tcpdump inside its namespace sees what reached it. tcpdump's packet
// socket needs CAP_NET_RAW: without it the medium's own capture (tests above) is the view.
TEST(TapbridgeCapture, TcpdumpInsideRobotSeesItsTraffic) {
  SITLNET_REQUIRE_ROOT();
  SITLNET_REQUIRE_CAPABILITY(CAP_NET_RAW, "tcpdump opens a packet socket on the robot's wlan0");
  MediumScenario scenario("tcd", 2, kTwo);
  scenario.StartDaemon();
  auto tcpdump = scenario.Spawn("b", {"tcpdump", "-n", "-l", "-i", "wlan0", "-c", "2", "icmp"});
  ASSERT_TRUE(tcpdump->WaitForOutput(true, "listening on wlan0", 10 * kNsPerS)) << tcpdump->err();
  ASSERT_TRUE(Pings(scenario, "a", 1, 1));
  ASSERT_EQ(tcpdump->Wait(10 * kNsPerS), 0) << tcpdump->err();
  EXPECT_NE(tcpdump->out().find(scenario.Address(0) + " > " + scenario.Address(1) +
                                ": ICMP echo request"),
            std::string::npos)
      << tcpdump->out();
}

TEST(TapbridgeBadInput, FramesAbove80211MtuDroppedAndCounted) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("mtu", 2, kTwo);
  scenario.StartDaemon();
  ASSERT_EQ(scenario.Exec("a", {"ip", "link", "set", "wlan0", "mtu", "4000"}).exit_code, 0);
  // 3000-byte ICMP payload: a 3042-byte Ethernet frame, above the 2310 an
  // 802.11 MSDU of 2304 bytes can carry.
  EXPECT_FALSE(scenario
                   .Exec("a", {PingProgram(), "-c", "1", "-W", "1", "-s", "3000", "-M", "do",
                               scenario.Address(1)})
                   .exit_code == 0);
  const proto::MediumStatus status = scenario.Counters();
  EXPECT_GE(status.station(0).oversize_dropped(), 1u);
  EXPECT_TRUE(Pings(scenario, "a", 1)) << "normal frames still pass";
}

// Documented behaviour (docs/tapbridge.md): frames whose source MAC is not
// the robot's plan MAC are dropped, counted, and logged once per robot.
TEST(TapbridgeBadInput, UnknownSourceMacDroppedCountedAndLogged) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("mac", 3, kTwo);
  scenario.StartDaemon();
  ASSERT_EQ(
      scenario.Exec("a", {"ip", "link", "set", "wlan0", "address", "02:00:00:aa:bb:01"}).exit_code,
      0);
  EXPECT_FALSE(Pings(scenario, "a", 1));
  EXPECT_GE(scenario.Counters().station(0).unknown_source_dropped(), 1u);
  EXPECT_TRUE(scenario.daemon()->WaitForOutput(true, "is not the robot's", 2 * kNsPerS));
  EXPECT_FALSE(Pings(scenario, "b", 0)) << "a's answers carry the changed MAC: dropped";
}

// The daemon is stopped (SIGSTOP) while a robot floods broadcast frames: the
// kernel's TAP queue overflows. Counted, not fatal: after SIGCONT traffic flows.
TEST(TapbridgeBadInput, TapOverflowCountedNotFatal) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("ovf", 4, kTwo);
  scenario.StartDaemon();
  ASSERT_TRUE(Pings(scenario, "a", 1));
  ASSERT_EQ(kill(scenario.daemon()->pid(), SIGSTOP), 0);
  // 40 MB in 8 KiB datagrams = ~4900 datagrams of 6 fragments each: ~29000
  // frames against a TAP queue of txqueuelen 10000.
  const std::string broadcast = scenario.Address(254);
  const CommandResult flood = scenario.Exec(
      "a", {"sh", "-c",
            "head -c 40000000 /dev/zero | socat -u - UDP4-DATAGRAM:" + broadcast + ":9,broadcast"});
  kill(scenario.daemon()->pid(), SIGCONT);
  EXPECT_EQ(flood.exit_code, 0) << flood.err;
  EXPECT_TRUE(Pings(scenario, "a", 1, 3));
  const proto::MediumStatus status = scenario.Counters();
  EXPECT_GT(status.station(0).kernel_tx_dropped(), 0u);
  EXPECT_GT(status.station(0).queue_drops(), 0u);
}

TEST(TapbridgeBadInput, DeletedNamespaceReportedOthersKeepRunning) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario(
      "del", 0, std::string(kTwo) + "robot { name: \"c\" position_m { x: 5 y: 5 z: 1 } }\n");
  scenario.StartDaemon();
  ASSERT_TRUE(Pings(scenario, "a", 2));
  ASSERT_EQ(RunCommand({"ip", "netns", "delete", scenario.Netns("c")}).exit_code, 0);
  EXPECT_TRUE(scenario.daemon()->WaitForOutput(true, "detached", 5 * kNsPerS))
      << scenario.daemon()->err();
  EXPECT_TRUE(Pings(scenario, "a", 1));
  EXPECT_FALSE(scenario.Counters().station(2).attached());
}

// A robot whose wlan0 is gone is reported in one line naming the robot and the device; the
// daemon exits and does not create a fresh (unconfigured, non-persistent) TAP in its place.
TEST(TapbridgeBadInput, MissingWlan0IsReportedNotRecreated) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("nwl", 2, kTwo);
  ASSERT_EQ(RunCommand({"ip", "-n", scenario.Netns("b"), "link", "delete", "wlan0"}).exit_code, 0);
  const CommandResult daemon =
      RunCommand({SitlnetBinary(), "medium", scenario.path()}, 10 * kNsPerS);
  EXPECT_NE(daemon.exit_code, 0);
  EXPECT_EQ(Lines(daemon.err), 1) << daemon.err;
  EXPECT_NE(daemon.err.find("robot b"), std::string::npos) << daemon.err;
  EXPECT_NE(daemon.err.find("\"wlan0\""), std::string::npos) << daemon.err;
  EXPECT_NE(daemon.err.find("no such device"), std::string::npos) << daemon.err;
  const CommandResult links = RunCommand({"ip", "-n", scenario.Netns("b"), "-o", "link", "show"});
  EXPECT_EQ(links.out.find("wlan0"), std::string::npos) << links.out;
}

// TAPs are persistent: a new daemon attaches to them again. A second daemon
// while one runs is refused.
TEST(TapbridgeBadInput, DaemonRestartReattaches) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("rst", 1, kTwo);
  scenario.StartDaemon();
  ASSERT_TRUE(Pings(scenario, "a", 1));
  const CommandResult second =
      RunCommand({SitlnetBinary(), "medium", scenario.path()}, 10 * kNsPerS);
  EXPECT_EQ(second.exit_code, 1) << "a second daemon for the same scenario is refused";
  EXPECT_NE(second.err.find("already serves"), std::string::npos) << second.err;
  const std::string log = scenario.StopDaemon();
  EXPECT_NE(log.find("stopping on SIGTERM"), std::string::npos) << log;
  EXPECT_FALSE(Pings(scenario, "a", 1, 1)) << "no daemon, no medium";
  scenario.StartDaemon();
  EXPECT_TRUE(Pings(scenario, "a", 1));
}

// The daemon asks for SCHED_FIFO kDefaultRealtimePriority (docs/tapbridge.md). With CAP_SYS_NICE
// it gets it; without (the min-caps pass) it says so in one line, stays SCHED_OTHER and serves the medium all the
// same. chrt (util-linux) observes the policy of the daemon's main thread, which asked.
TEST(TapbridgeDaemon, SchedFifoWithCapSysNiceElseOneWarningAndNormalPriority) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("fif", 2, kTwo);
  scenario.StartDaemon();
  ASSERT_TRUE(Pings(scenario, "a", 1));
  const CommandResult chrt = RunCommand({"chrt", "-p", std::to_string(scenario.daemon()->pid())});
  ASSERT_EQ(chrt.exit_code, 0) << chrt.err;
  const std::string log = scenario.StopDaemon();
  const std::string warning = "SCHED_FIFO priority " + std::to_string(kDefaultRealtimePriority) +
                              " refused (needs CAP_SYS_NICE or RLIMIT_RTPRIO)";
  if (integration_test::HasCapability(CAP_SYS_NICE)) {
    EXPECT_NE(chrt.out.find("policy: SCHED_FIFO"), std::string::npos) << chrt.out;
    EXPECT_NE(chrt.out.find("priority: " + std::to_string(kDefaultRealtimePriority)),
              std::string::npos)
        << chrt.out;
    EXPECT_EQ(log.find(warning), std::string::npos) << log;
  } else {
    EXPECT_NE(chrt.out.find("policy: SCHED_OTHER"), std::string::npos) << chrt.out;
    const size_t first = log.find(warning);
    EXPECT_NE(first, std::string::npos) << log;
    EXPECT_EQ(log.find(warning, first + 1), std::string::npos) << "one warning: " << log;
  }
}

}  // namespace
}  // namespace sitlnet::tapbridge::testing

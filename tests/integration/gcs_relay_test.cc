// Issue 47: `sitlnet run` joins a ground station's MAVLink to a GCS on the host by itself
// (gcs_link/, docs/autopilots.md "Ground stations"). The vehicles are sitlnet's test autopilot
// (HEARTBEAT each second of its clock, GLOBAL_POSITION_INT at 10 Hz, system id = robot index + 1);
// the GCS is node-mavlink (tests/node_mavlink/host_gcs.cjs), an implementation sitlnet did not
// write. Oracles: what the GCS decoded, the commands as they crossed the medium (medium.pcap),
// gcs.tlog read back by node-mavlink (read_tlog.cjs), and the time each telemetry frame carries.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::Child;
using integration_test::ReadAll;
using integration_test::SitlnetBinary;
using integration_test::TempDir;

constexpr int kSlot = 14;  // A binary of its own: its pid keeps its subnets apart.
constexpr TimeNs kIterationNs = 10 * kNsPerMs;  // scenario.proto's default timing

// A station (index 0, no image: the relay serves it) and two test autopilots sending it their
// telemetry, one on each simulator protocol: system ids 2 and 3.
// `extra_vehicle`: a third, a test autopilot at robot index 3 (system id 4), in slot `slot`.
RunScenario WriteRelayScenario(int duration_ms, int slot = kSlot, bool extra_vehicle = false) {
  const std::string station = WlanPrefix(slot) + "1";
  const std::string extra =
      !extra_vehicle ? ""
                     : "robot { name: \"ap4\" position_m { x: 0 y: 5 z: 0.2 } image: "
                       "\"test_autopilot\" ardupilot_json_port: 9002 args: [\"--json-port\", "
                       "\"9002\", \"--telemetry\", \"" +
                           station + ":14550\"] }\n";
  return WriteScenario(
      slot, RelayFleetRobots(slot) + extra,
      "timing { duration_ms: " + std::to_string(duration_ms) + " pacing: PACING_REALTIME }\n");
}

int CountLines(const std::string& text, const std::string& prefix) {
  int count = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) count += line.rfind(prefix, 0) == 0;
  return count;
}

// What node-mavlink decoded of one system id at the GCS: its messages, the frames missing by
// each component's sequence numbers, and its latest HEARTBEAT's base_mode and custom_mode.
struct Heard {
  int messages = 0;
  int sequence_gaps = 0;
  int base_mode = -1, custom_mode = -1;
};
std::map<int, Heard> HeardBySystem(const std::string& gcs_output) {
  std::map<int, Heard> heard;
  std::map<std::pair<int, int>, int> last_sequence;
  std::istringstream lines(gcs_output);
  for (std::string line; std::getline(lines, line);) {
    int sysid = 0, msgid = 0, wall_ms = 0, compid = 0, seq = 0, base_mode = 0, custom_mode = 0;
    char name[64];
    const int fields =
        std::sscanf(line.c_str(),
                    "HEARD sysid=%d msgid=%d name=%63s wall_ms=%d compid=%d seq=%d "
                    "base_mode=%d custom_mode=%d",
                    &sysid, &msgid, name, &wall_ms, &compid, &seq, &base_mode, &custom_mode);
    if (fields < 6) continue;
    Heard& system = heard[sysid];
    ++system.messages;
    const auto [at, first] = last_sequence.try_emplace({sysid, compid}, seq);
    if (!first) system.sequence_gaps += (seq - at->second - 1 + 256) % 256;
    at->second = seq;
    if (fields == 8) {
      system.base_mode = base_mode;
      system.custom_mode = custom_mode;
    }
  }
  return heard;
}

// The virtual times (ns) at which the medium delivered a frame from each robot to robot 0, the
// station (deliveries.csv), ascending.
std::map<int, std::vector<TimeNs>> DeliveriesToStation(const std::string& out) {
  std::map<int, std::vector<TimeNs>> deliveries;
  std::istringstream lines(ReadAll(out + "/deliveries.csv"));
  for (std::string line; std::getline(lines, line);) {
    int64_t time_ns = 0;
    int from = 0, to = 0;
    if (std::sscanf(line.c_str(), "%" SCNd64 ",%d,%d", &time_ns, &from, &to) == 3 && to == 0) {
      deliveries[from].push_back(time_ns);
    }
  }
  return deliveries;
}

double Relayed(const std::string& summary, const std::string& counter) {
  return SummaryNumber(summary, "\"gcs_relay\":", "\"" + counter + "\":");
}

// The relay both ways, and gcs.tlog, with a GCS that floods the relay with junk: 3 datagrams
// that begin no frame for each datagram it hears.
TEST(GcsRelayTest, AHostGcsHearsEveryVehicleCommandsEachAndJunkNeverReachesTheRadio) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(NodeMavlinkMissing());
  std::optional<Child> gcs;
  const int port = StartHostGcs(&gcs, {"0", "0", "3"});
  ASSERT_NE(port, 0) << gcs->out() << gcs->err();
  const RunScenario scenario = WriteRelayScenario(4000);
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult run =
      SitlnetRun(scenario, out, {"--gcs", "udp:127.0.0.1:" + std::to_string(port)});
  kill(gcs->pid(), SIGTERM);
  ASSERT_EQ(gcs->Wait(10 * kNsPerS), 0);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string heard = gcs->out();
  const std::string summary = ReadAll(out + "/summary.json");

  // Every vehicle's heartbeat reached the GCS, every frame valid to node-mavlink.
  const std::map<int, int> first = FirstHeartbeatMs(heard);
  EXPECT_TRUE(first.count(2) && first.count(3)) << heard.substr(0, 2000);
  EXPECT_NE(heard.find(" invalid=0 unknown=0"), std::string::npos) << heard;
  const int frames_heard = CountLines(heard, "HEARD ");
  EXPECT_EQ(frames_heard, Relayed(summary, "from_vehicles")) << summary;
  EXPECT_EQ(frames_heard, Relayed(summary, "to_gcs")) << summary;
  EXPECT_EQ(Relayed(summary, "to_gcs_unreceived"), 0) << summary;

  // Per vehicle, the relay's counts are what node-mavlink decoded at the GCS (every datagram
  // reached it: none unreceived): messages, sequence gaps, the latest heartbeat. The test
  // autopilot is armed (MAV_MODE_FLAG_SAFETY_ARMED, 128) from 0.5 s on.
  for (const auto& [sysid, decoded] : HeardBySystem(heard)) {
    const std::string vehicle = "\"system_id\":" + std::to_string(sysid) + ",";
    EXPECT_EQ(SummaryNumber(summary, vehicle, "\"messages\":"), decoded.messages) << sysid;
    EXPECT_EQ(SummaryNumber(summary, vehicle, "\"sequence_gaps\":"), decoded.sequence_gaps)
        << sysid;
    EXPECT_EQ(SummaryNumber(summary, vehicle, "\"base_mode\":"), decoded.base_mode) << sysid;
    EXPECT_EQ(SummaryNumber(summary, vehicle, "\"custom_mode\":"), decoded.custom_mode) << sysid;
    EXPECT_EQ(decoded.base_mode & 128, 128) << sysid;
    const size_t at = summary.find(vehicle);
    EXPECT_NE(summary.find("\"armed\":true", at), std::string::npos) << summary;
    // Its robot: the test autopilot's system id is its robot index + 1 (the view's row for it).
    const char* robot = sysid == 2 ? "ap" : "px";
    EXPECT_NE(summary.find(vehicle + "\"address\":\"" + WlanPrefix(kSlot) + std::to_string(sysid) +
                           "\",\"robot\":\"" + robot + "\""),
              std::string::npos)
        << summary;
    std::printf("[ measured ] system %d: %d messages, %d missing by sequence, base_mode %d\n",
                sysid, decoded.messages, decoded.sequence_gaps, decoded.base_mode);
  }

  // Its command to each vehicle crossed the radio from the station to that vehicle alone (routed
  // by its target_system), and only the commands did: the junk (4 bytes a datagram) was counted
  // and dropped.
  const int commands = CountLines(heard, "SENT ");
  EXPECT_EQ(commands, 2) << heard;
  const std::string station = WlanPrefix(kSlot) + "1";
  int on_air = 0;
  for (const char* vehicle : {"2", "3"}) {
    const size_t to_vehicle =
        CapturedTimes(out, "ip.src == " + station + " && ip.dst == " + WlanPrefix(kSlot) + vehicle +
                               " && udp.srcport == 14550")
            .size();
    EXPECT_EQ(to_vehicle, 1u) << "to " << vehicle;
    on_air += static_cast<int>(to_vehicle);
  }
  EXPECT_EQ(on_air, Relayed(summary, "to_vehicles")) << summary;
  EXPECT_EQ(Relayed(summary, "to_vehicles_routed"), commands) << summary;
  const double junk = Relayed(summary, "from_gcs_without_frame");
  EXPECT_EQ(junk, 3.0 * frames_heard) << summary;
  EXPECT_EQ(Relayed(summary, "from_gcs"), junk + commands) << summary;
  EXPECT_EQ(Relayed(summary, "from_gcs_bytes_dropped"), 4 * junk) << summary;

  // gcs.tlog holds every frame both ways, each valid to node-mavlink, stamped in the
  // simulation's clock: a telemetry frame no earlier than the iteration of the time it carries,
  // and within 50 ms after the medium delivered a frame of its vehicle to the station
  // (deliveries.csv; the 50 ms are slack for the relay's wake-up on a busy host, not a derived
  // bound). Not within 50 ms of the time it carries: a vehicle's kernel may hold its datagrams
  // while ARP resolves the station, 1 s per lost ARP request (measured once: 1.03 s).
  const std::map<int, std::vector<TimeNs>> delivered = DeliveriesToStation(out);
  const CommandResult tlog =
      RunCommand({"node", NodeMavlinkDir() + "/read_tlog.cjs", out + "/gcs.tlog"});
  ASSERT_EQ(tlog.exit_code, 0) << tlog.err;
  const int entries = frames_heard + commands;
  EXPECT_NE(tlog.out.find("COUNTS entries=" + std::to_string(entries) +
                          " valid=" + std::to_string(entries) + " invalid=0 unknown=0 trailing=0"),
            std::string::npos)
      << tlog.out.substr(tlog.out.size() > 300 ? tlog.out.size() - 300 : 0);
  EXPECT_EQ(Relayed(summary, "tlog_frames"), entries) << summary;
  int stamped = 0;
  TimeNs latest_ns = 0;  // The largest stamp past the delivery before it.
  std::istringstream lines(tlog.out);
  for (std::string line; std::getline(lines, line);) {
    int64_t stamp_us = 0, boot_ms = 0;
    int sysid = 0, msgid = 0;
    if (std::sscanf(line.c_str(),
                    "ENTRY stamp_us=%" SCNd64 " sysid=%d msgid=%d name=%*s time_boot_ms=%" SCNd64,
                    &stamp_us, &sysid, &msgid, &boot_ms) != 4) {
      continue;
    }
    const TimeNs carried_ns = boot_ms * kNsPerMs;
    const TimeNs stamp_ns = stamp_us * kNsPerUs;
    EXPECT_GE(stamp_ns, carried_ns / kIterationNs * kIterationNs) << line;
    // The vehicle's robot index is its system id - 1; the last delivery before the stamp.
    const std::vector<TimeNs>& from_vehicle =
        delivered.count(sysid - 1) ? delivered.at(sysid - 1) : std::vector<TimeNs>{};
    const auto after = std::upper_bound(from_vehicle.begin(), from_vehicle.end(), stamp_ns);
    ASSERT_NE(after, from_vehicle.begin()) << line << ": stamped before any delivery";
    EXPECT_LE(stamp_ns - *(after - 1), 50 * kNsPerMs) << line;
    latest_ns = std::max(latest_ns, stamp_ns - *(after - 1));
    ++stamped;
  }
  EXPECT_GE(stamped, 60) << "GLOBAL_POSITION_INT at 10 Hz from 2 vehicles for 4 s";
  std::printf(
      "[ measured ] %d frames heard, %d in gcs.tlog; %d position frames stamped at most "
      "%.3f ms after a delivery to the station; %.0f junk datagrams dropped\n",
      frames_heard, entries, stamped, static_cast<double>(latest_ns) / kNsPerMs, junk);
  ExpectNothingLeft(scenario.name);
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", out});
}

// A GCS that starts after the run and one that restarts: datagrams with nobody listening are
// counted (the kernel refuses them with ICMP port unreachable, which loopback never
// rate-limits) and end nothing; each GCS instance hears every vehicle's heartbeat within a second
// of binding its port (a heartbeat each simulated second, realtime factor 1; 100 ms slack for
// the radio and the host's scheduling, not derived).
TEST(GcsRelayTest, AGcsThatStartsLateAndRestartsHearsEveryVehicleWithinASecond) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const int port = FreePort(SOCK_DGRAM);
  ASSERT_NE(port, 0);
  const RunScenario scenario = WriteRelayScenario(12000);
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-late-out";
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress", "--gcs",
             "udp:127.0.0.1:" + std::to_string(port)});
  ASSERT_TRUE(run.WaitForOutput(true, "relayed to", 60 * kNsPerS)) << run.err();
  // The relay's socket in the station gave it no route: only its own subnets' (as every robot,
  // NnsUpTest.ThreeRobotsHaveTheSpecifiedDevicesAddressesAndRoutes), no default route.
  const CommandResult routes = RunCommand({"ip", "-n", scenario.name + "-gcs", "route", "show"});
  ASSERT_EQ(routes.exit_code, 0) << routes.err;
  EXPECT_EQ(routes.out.find("default"), std::string::npos) << routes.out;
  EXPECT_EQ(CountLines(routes.out, ""), 2) << routes.out;  // wlan0's subnet and ctl0's /30
  // The stimulus, not a synchronisation: the GCS starts 3 s (wall) after the relay.
  std::this_thread::sleep_for(std::chrono::seconds(3));
  for (int instance = 1; instance <= 2; ++instance) {
    std::optional<Child> gcs;
    ASSERT_EQ(StartHostGcs(&gcs, {std::to_string(port), "2"}), port) << gcs->out() << gcs->err();
    ASSERT_EQ(gcs->Wait(30 * kNsPerS), 0) << gcs->err();
    const std::map<int, int> first = FirstHeartbeatMs(gcs->out());
    for (int sysid : {2, 3}) {
      ASSERT_TRUE(first.count(sysid)) << "instance " << instance << ", system " << sysid << "\n"
                                      << gcs->out().substr(0, 2000);
      EXPECT_LE(first.at(sysid), 1100) << "instance " << instance << ", system " << sysid;
      std::printf("[ measured ] GCS instance %d: system %d's first heartbeat %d ms after binding\n",
                  instance, sysid, first.at(sysid));
    }
  }
  ASSERT_EQ(run.Wait(60 * kNsPerS), 0) << run.err();
  const std::string summary = ReadAll(out + "/summary.json");
  // 3 s without a GCS: about 66 datagrams (2 vehicles, 11 a second); 20 is a loose floor.
  EXPECT_GE(Relayed(summary, "to_gcs_unreceived"), 20) << summary;
  EXPECT_EQ(Relayed(summary, "to_gcs"), Relayed(summary, "from_vehicles")) << summary;
  std::printf("[ measured ] %s\n", summary.substr(summary.find("\"gcs_relay\":"), 400).c_str());
  ExpectNothingLeft(scenario.name);
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", out});
}

// `--gcs tcp-listen:PORT`: a GCS that connects over TCP (as MAVProxy and QGroundControl connect to
// ArduPilot SITL's 5760) hears every vehicle, its commands reach each vehicle alone, and junk it
// writes (8 bytes) is dropped, counted by the byte.
TEST(GcsRelayTest, AGcsConnectedOverTcpHearsEveryVehicleAndCommandsEach) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const int port = FreePort(SOCK_STREAM);
  ASSERT_NE(port, 0);
  const RunScenario scenario = WriteRelayScenario(6000);
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-tcp-out";
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress", "--gcs",
             "tcp-listen:" + std::to_string(port)});
  ASSERT_TRUE(run.WaitForOutput(true, "relayed to", 60 * kNsPerS)) << run.err();
  Child gcs({"node", NodeMavlinkDir() + "/host_gcs.cjs", "tcp:" + std::to_string(port), "0", "2"});
  ASSERT_TRUE(gcs.WaitForOutput(false, "CONNECTED", 30 * kNsPerS)) << gcs.out() << gcs.err();
  ASSERT_EQ(run.Wait(60 * kNsPerS), 0) << run.err();
  kill(gcs.pid(), SIGTERM);
  ASSERT_EQ(gcs.Wait(10 * kNsPerS), 0)
      << gcs.err() << gcs.out().substr(gcs.out().size() > 300 ? gcs.out().size() - 300 : 0);
  const std::string heard = gcs.out();
  const std::string summary = ReadAll(out + "/summary.json");
  const std::map<int, int> first = FirstHeartbeatMs(heard);
  EXPECT_TRUE(first.count(2) && first.count(3)) << heard.substr(0, 2000);
  EXPECT_NE(heard.find(" invalid=0 unknown=0"), std::string::npos) << heard;
  EXPECT_EQ(CountLines(heard, "SENT "), 2) << heard;
  for (const char* vehicle : {"2", "3"}) {
    EXPECT_EQ(CapturedTimes(out, "ip.src == " + WlanPrefix(kSlot) + "1 && ip.dst == " +
                                     WlanPrefix(kSlot) + vehicle + " && udp.srcport == 14550")
                  .size(),
              1u)
        << "to " << vehicle;
  }
  EXPECT_EQ(Relayed(summary, "gcs_clients"), 1) << summary;
  EXPECT_EQ(Relayed(summary, "to_vehicles_routed"), 2) << summary;
  EXPECT_EQ(Relayed(summary, "from_gcs_bytes_dropped"), 8) << summary;
  std::printf(
      "[ measured ] over TCP: %d frames heard, first heartbeats %d and %d ms after "
      "connecting\n",
      CountLines(heard, "HEARD "), first.count(2) ? first.at(2) : -1,
      first.count(3) ? first.at(3) : -1);
  ExpectNothingLeft(scenario.name);
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", out});
}

// Two runs at once, each with a GCS on a port of its own (`--gcs udp:127.0.0.1:PORT`): neither
// relay collides with the other, and each GCS hears its own run's vehicles only (the second run
// has a third vehicle, system id 4, that the first GCS must never hear).
TEST(GcsRelayTest, TwoRunsAtOnceEachReachTheirOwnGcs) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(NodeMavlinkMissing());
  std::optional<Child> gcs_a, gcs_b;
  const int port_a = StartHostGcs(&gcs_a, {"0", "0"});
  const int port_b = StartHostGcs(&gcs_b, {"0", "0"});
  ASSERT_TRUE(port_a != 0 && port_b != 0);
  const RunScenario a = WriteRelayScenario(4000, kSlot);
  const RunScenario b = WriteRelayScenario(4000, kSlot + 1, true);
  DownGuard guard_a(a.name), guard_b(b.name);
  const std::string out_a = TempDir() + "/" + a.name + "-a-out";
  const std::string out_b = TempDir() + "/" + b.name + "-b-out";
  Child run_a({SitlnetBinary(), "run", a.path, "--out", out_a, "--no-progress", "--gcs",
               "udp:127.0.0.1:" + std::to_string(port_a)});
  Child run_b({SitlnetBinary(), "run", b.path, "--out", out_b, "--no-progress", "--gcs",
               "udp:127.0.0.1:" + std::to_string(port_b)});
  ASSERT_EQ(run_a.Wait(120 * kNsPerS), 0) << run_a.err();
  ASSERT_EQ(run_b.Wait(120 * kNsPerS), 0) << run_b.err();
  for (std::optional<Child>* gcs : {&gcs_a, &gcs_b}) {
    kill((*gcs)->pid(), SIGTERM);
    ASSERT_EQ((*gcs)->Wait(10 * kNsPerS), 0);
  }
  const std::map<int, Heard> heard_a = HeardBySystem(gcs_a->out());
  const std::map<int, Heard> heard_b = HeardBySystem(gcs_b->out());
  EXPECT_TRUE(heard_a.count(2) && heard_a.count(3)) << gcs_a->out().substr(0, 1000);
  EXPECT_FALSE(heard_a.count(4)) << "the other run's vehicle reached this GCS";
  EXPECT_TRUE(heard_b.count(2) && heard_b.count(3) && heard_b.count(4))
      << gcs_b->out().substr(0, 1000);
  for (const std::string& out : {out_a, out_b}) {
    const std::string summary = ReadAll(out + "/summary.json");
    EXPECT_EQ(Relayed(summary, "to_gcs_unreceived"), 0) << summary;
  }
  std::printf("[ measured ] two runs at once: GCS A heard %zu systems, GCS B %zu\n", heard_a.size(),
              heard_b.size());
  ExpectNothingLeft(a.name);
  ExpectNothingLeft(b.name);
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", out_a, out_b});
}

}  // namespace
}  // namespace sitlnet::nns::testing

// Autopilots in `sitlnet run` (issue 14, docs/autopilots.md): sitlnet's test autopilot speaking
// ArduPilot's JSON protocol and PX4's simulator MAVLink, in the coordinator's clock, its
// telemetry to a ground station over the simulated radio checked with node-mavlink (an
// implementation sitlnet did not write), a silent autopilot, and the ground-station relay.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "tests/integration/run_test_util.h"
#include "tests/integration/served_on_time.h"

namespace sitlnet::nns::testing {
namespace {

// "reply N t=S pos=X,Y,Z" lines of a test autopilot's --log-replies: (t, simulator's position).
std::vector<std::pair<double, std::array<double, 3>>> AutopilotReplies(const std::string& log) {
  std::vector<std::pair<double, std::array<double, 3>>> replies;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    unsigned long long n = 0;
    double t = 0;
    std::array<double, 3> p{};
    if (std::sscanf(line.c_str(), "reply %llu t=%lf pos=%lf,%lf,%lf", &n, &t, &p[0], &p[1],
                    &p[2]) == 5) {
      replies.emplace_back(t, p);
    }
  }
  return replies;
}

// Every row of `robot` in trajectories.csv (time_s,robot,x_m,y_m,z_m,..., every 100 ms) after
// t = 0 that falls on a reply is the reply's position within `tolerance_m`. Returns how many.
int CompareTrajectory(const std::string& csv, int robot,
                      const std::vector<std::pair<double, std::array<double, 3>>>& replies,
                      double reply_period_s, double first_reply_s, double tolerance_m) {
  std::istringstream rows(csv);
  int compared = 0;
  for (std::string row; std::getline(rows, row);) {
    double t = 0, x = 0, y = 0, z = 0;
    int r = -1;
    if (std::sscanf(row.c_str(), "%lf,%d,%lf,%lf,%lf", &t, &r, &x, &y, &z) != 5 || r != robot ||
        t == 0) {
      continue;
    }
    const long n = std::lround((t - first_reply_s) / reply_period_s);
    if (n < 0 || n >= static_cast<long>(replies.size())) continue;  // The run's end: no reply.
    EXPECT_NEAR(replies[n].first, t, 1e-9) << "robot " << robot;
    EXPECT_NEAR(replies[n].second[0], x, tolerance_m) << "robot " << robot << " at " << t;
    EXPECT_NEAR(replies[n].second[1], y, tolerance_m) << "robot " << robot << " at " << t;
    EXPECT_NEAR(replies[n].second[2], z, tolerance_m) << "robot " << robot << " at " << t;
    ++compared;
  }
  return compared;
}

// A MAVLink message as node-mavlink decoded it, with the on-air time of its datagram.
struct DecodedMessage {
  double on_air_s = 0;
  std::map<std::string, std::string> fields;  // "id", "name", "sysid", field names ...
};

// The UDP payloads of the capture's first transmissions matching `filter` (not ICMP errors that
// quote them), each one MAVLink message, decoded by node-mavlink (tests/node_mavlink/decode.cjs,
// CRC and CRC_EXTRA checked). `counts`: its "COUNTS valid=.. invalid=.. unknown=.." line.
std::vector<DecodedMessage> DecodeTelemetry(const std::string& out, const std::string& filter,
                                            std::string* counts) {
  const CommandResult tshark = RunCommand({"tshark", "-r", out + "/medium.pcap", "-Y",
                                           "(" + filter + ") && wlan.fc.retry == 0 && !icmp", "-T",
                                           "fields", "-e", "frame.time_epoch", "-e", "data.data"},
                                          60 * kNsPerS);
  EXPECT_EQ(tshark.exit_code, 0) << tshark.err;
  std::vector<double> times;
  std::string bytes;
  std::istringstream lines(tshark.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    double time = 0;
    std::string hex;
    fields >> time >> hex;
    times.push_back(time);
    for (size_t i = 0; i + 1 < hex.size(); i += 2) {
      bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
  }
  const std::string stream = out + "/telemetry.bin";
  std::ofstream(stream, std::ios::binary) << bytes;
  const CommandResult node = RunCommand(
      {"sh", "-c", "node \"$0/decode.cjs\" < \"$1\"", NodeMavlinkDir(), stream}, 60 * kNsPerS);
  EXPECT_EQ(node.exit_code, 0) << node.err;
  std::vector<DecodedMessage> messages;
  std::istringstream decoded(node.out);
  for (std::string line; std::getline(decoded, line);) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "COUNTS") {
      *counts = line;
      continue;
    }
    DecodedMessage message;
    words >> message.fields["id"] >> message.fields["name"];
    for (std::string word; words >> word;) {
      const size_t eq = word.find('=');
      message.fields[word.substr(0, eq)] = word.substr(eq + 1);
    }
    messages.push_back(std::move(message));
  }
  // One message per datagram: the n-th decoded is the n-th captured.
  EXPECT_EQ(messages.size(), times.size());
  for (size_t i = 0; i < std::min(messages.size(), times.size()); ++i) {
    messages[i].on_air_s = times[i];
  }
  return messages;
}

// Issue 14, items 1, 2, 4 and 5 end to end: three ArduPilot robots and three PX4 robots (the
// test autopilot speaking each protocol as the autopilot does), a native flocker and a ground
// station, in lockstep pacing:
// - each ArduPilot reply's timestamp is its frame's end on the 400 Hz grid (2.5 ms); each PX4
//   HIL_SENSOR's is on PX4's 4 ms grid from 0: the clock waited for every answer and released
//   every message when it reached that time;
// - the positions the medium uses (trajectories.csv, the poses the coordinator passes on) are
//   the autopilots' at the same virtual time (PX4's ground truth to its degE7 resolution);
// - every autopilot's MAVLink telemetry (HEARTBEAT, GLOBAL_POSITION_INT) reaches the ground
//   station over the medium, decoded by node-mavlink with no invalid frame, and enters the
//   medium in the iteration of the time it carries;
// - two runs with the same seed are byte-identical (trajectories, capture, deliveries);
// - each autopilot climbs to 5 m and flies towards its waypoint from its protocol alone.
TEST(RunTest, ArduPilotAndPx4RobotsFlyInTheCoordinatorsClockAndTwoRunsAreByteIdentical) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const std::string wlan = WlanPrefix(12);
  const std::string station = wlan + "8";  // robot 7
  // The station listens on 14550 from before the run's start, as a GCS does: a port without a
  // listener would answer with ICMP errors, whose rate limit follows the host's clock.
  const std::string sink = TempDir() + "/gcs_sink.textproto";
  std::ofstream(sink) << "name: \"gcs_sink\"\ncommand: \"/bin/sh\"\ncommand: \"-c\"\n"
                         "command: \"exec socat -d -d -u UDP4-RECV:14550 OPEN:/dev/null\"\n"
                         "ready_log_line: \"starting data transfer loop\"\n";
  std::string robots;
  for (int i = 0; i < 6; ++i) {
    const bool px4 = i >= 3;
    const double y = 4.0 * i;
    char text[512];
    std::snprintf(text, sizeof text,
                  "robot { name: \"%s%d\" position_m { x: 0 y: %g z: 0.2 } image: "
                  "\"test_autopilot\" %s args: [\"%s\", \"%s\", \"--telemetry\", \"%s:14550\", "
                  "\"--log-replies\", \"--altitude-m\", \"5\", \"--waypoint\", \"15,%g\"] }\n",
                  px4 ? "px" : "ap", i % 3 + 1, y,
                  px4 ? "px4_sim_port: 4560" : "ardupilot_json_port: 9002",
                  px4 ? "--px4-port" : "--json-port", px4 ? "4560" : "9002", station.c_str(), y);
    robots += text;
  }
  robots +=
      "robot { name: \"f\" position_m { x: -6 y: 0 z: 0.2 } image: \"flocker\" "
      "args: [\"--target\", \"-40,0\"] lidar { rays: 8 } }\n"
      "robot { name: \"gcs\" position_m { x: 6 y: 10 z: 2 } ground_station: true image: \"" +
      sink + "\" }\n";
  const RunScenario scenario =
      WriteScenario(12, robots, "timing { duration_ms: 8000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult first = SitlnetRun(scenario, out + "1", {"--seed", "4"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const CommandResult second = SitlnetRun(scenario, out + "2", {"--seed", "4"});
  ASSERT_EQ(second.exit_code, 0) << second.err;
  for (const char* file : {"trajectories.csv", "medium.pcap", "deliveries.csv"}) {
    EXPECT_EQ(RunCommand({"cmp", out + "1/" + file, out + "2/" + file}).exit_code, 0) << file;
  }
  const std::string trajectories = ReadAll(out + "1/trajectories.csv");
  for (int i = 0; i < 6; ++i) {
    const bool px4 = i >= 3;
    const std::string name = std::string(px4 ? "px" : "ap") + std::to_string(i % 3 + 1);
    const auto replies = AutopilotReplies(ReadAll(out + "1/robots/" + name + ".log"));
    // 8 s; the message due at the run's very end would leave at the next iteration's start.
    // ArduPilot's replies end its frames (first at 2.5 ms); PX4's first HIL_SENSOR is at 0.
    const double period_s = px4 ? 0.004 : 0.0025;
    const double first_s = px4 ? 0 : 0.0025;
    ASSERT_EQ(replies.size(), px4 ? 2000u : 3199u) << name;
    for (size_t n = 0; n < replies.size(); ++n) {
      // ArduPilot's frame ends fall on whole physics steps (1 ms): 2, 5, 7, 10 ms, ...
      const double expected_s = px4 ? n * period_s : std::floor((n + 1) * 2.5) / 1000;
      ASSERT_NEAR(replies[n].first, expected_s, 1e-9) << name << " reply " << n;
    }
    // PX4's ground truth is in degE7 (1.1 cm of latitude) and mm.
    EXPECT_EQ(CompareTrajectory(trajectories, i, replies, period_s, first_s, px4 ? 0.01 : 1e-3), 79)
        << name;
    const auto& [end_s, end_position] = replies.back();
    EXPECT_NEAR(end_position[2], 5, 0.5) << name << ": altitude at " << end_s << " s";
    EXPECT_GT(end_position[0], 7) << name << ": towards its waypoint (15, " << 4 * i << ")";
    EXPECT_NEAR(end_position[1], 4 * i, 0.5) << name;
  }
  // Telemetry to the station: HEARTBEAT each second, GLOBAL_POSITION_INT at 10 Hz of each
  // autopilot's clock (MAVLink system id: robot index + 1), each entering the medium in the
  // iteration (10 ms) of the time it carries. It goes on air DIFS (34 us) after it enters the
  // medium at the earliest, later if the medium is busy (a backoff of up to 15 slots, others'
  // frames): the 1 ms past the iteration is slack for that, not a derived bound; a message
  // stamped in the wrong iteration is 10 ms off.
  std::string counts;
  const std::vector<DecodedMessage> telemetry =
      DecodeTelemetry(out + "1", "udp.dstport == 14550 && ip.dst == " + station, &counts);
  EXPECT_NE(counts.find("invalid=0 unknown=0"), std::string::npos) << counts;
  std::map<std::string, int> heartbeats, positions;
  for (const DecodedMessage& message : telemetry) {
    const std::string& system = message.fields.at("sysid");
    if (message.fields.at("name") == "HEARTBEAT") {
      ++heartbeats[system];
      continue;
    }
    ASSERT_EQ(message.fields.at("name"), "GLOBAL_POSITION_INT");
    ++positions[system];
    const double autopilot_s = std::stod(message.fields.at("time_boot_ms")) / 1000;
    const double iteration_start_s = std::floor(autopilot_s * 100 + 1e-9) / 100;
    EXPECT_GE(message.on_air_s, iteration_start_s) << "system " << system << " at " << autopilot_s;
    EXPECT_LT(message.on_air_s, iteration_start_s + 0.01 + 0.001)
        << "system " << system << " at " << autopilot_s;
  }
  // The ArduPilot robots' reports (the state their reply gave, on the 100 ms grid as the rows)
  // are where trajectories.csv puts them on Earth, to the report's degE7 and mm: two projections
  // (the autopilot's tangent plane, sitlnet's azimuthal equidistant one) within a centimetre.
  std::map<std::pair<int, long>, std::array<double, 3>> geodetic_rows;  // (robot, t in 100 ms)
  {
    std::istringstream rows(trajectories);
    for (std::string row; std::getline(rows, row);) {
      double t = 0, skip[10], lat = 0, lon = 0, alt = 0;
      int robot = -1;
      if (std::sscanf(row.c_str(), "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t,
                      &robot, &skip[0], &skip[1], &skip[2], &skip[3], &skip[4], &skip[5], &skip[6],
                      &skip[7], &skip[8], &skip[9], &lat, &lon, &alt) == 15) {
        geodetic_rows[{robot, std::lround(t * 10)}] = {lat, lon, alt};
      }
    }
  }
  int located = 0;
  for (const DecodedMessage& message : telemetry) {
    const int system = std::stoi(message.fields.at("sysid"));
    if (message.fields.at("name") != "GLOBAL_POSITION_INT" || system > 3) continue;
    const long ms = std::stol(message.fields.at("time_boot_ms"));
    const auto row = geodetic_rows.find({system - 1, ms / 100});
    if (ms % 100 != 0 || row == geodetic_rows.end()) continue;
    EXPECT_NEAR(std::stod(message.fields.at("lat")), row->second[0] * 1e7, 1.5)
        << system << " " << ms;
    EXPECT_NEAR(std::stod(message.fields.at("lon")), row->second[1] * 1e7, 1.5)
        << system << " " << ms;
    EXPECT_NEAR(std::stod(message.fields.at("alt")), row->second[2] * 1e3, 2)
        << system << " " << ms;
    ++located;
  }
  EXPECT_GE(located, 3 * 70);
  EXPECT_NE(ReadAll(out + "1/summary.json")
                .find("\"geodetic_origin\":{\"latitude_deg\":47.397742,\"longitude_deg\":8.545594,"
                      "\"altitude_m\":488}"),
            std::string::npos);
  for (int system = 1; system <= 6; ++system) {
    EXPECT_EQ(heartbeats[std::to_string(system)], 8) << "system " << system;
    EXPECT_GE(positions[std::to_string(system)], 70) << "system " << system;
  }
  // The last position report of each autopilot: 5 m above home, as the flight log says.
  for (auto it = telemetry.rbegin(); it != telemetry.rend(); ++it) {
    if (it->fields.at("name") != "GLOBAL_POSITION_INT") continue;
    EXPECT_NEAR(std::stod(it->fields.at("relative_alt")), 5000, 500) << it->fields.at("sysid");
    break;
  }
  // deliveries.csv: the station (robot 7) received each autopilot's telemetry over the medium.
  const CommandResult delivered =
      RunCommand({"awk", "-F,",
                  "$3 == 7 && $2 <= 5 {n[$2]++} END {for (i = 0; i < 6; i++) "
                  "printf \"%d \", n[i] + 0}",
                  out + "1/deliveries.csv"});
  std::istringstream counts_by_robot(delivered.out);
  for (int robot = 0; robot < 6; ++robot) {
    int n = 0;
    counts_by_robot >> n;
    EXPECT_GE(n, 80) << "to the station from robot " << robot;
  }
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out + "1", out + "2", sink});
}

// Issue 14, item 1: in realtime pacing each autopilot message leaves at the wall instant of its
// virtual time (the physics computes an iteration ahead of the wall clock, and holds them).
// Measured from the test autopilot's log: the wall time it took each observation, less the
// observation's virtual time, is one constant (the run's start) plus the host's delay. Served at
// once, at the start of its 10 ms iteration, a message at phase p ms into the iteration would come
// p ms early: the offsets of late-phase messages would lie about 6 ms below those of early-phase
// ones (medians of phases under 3 ms and of 6 ms and over; ArduPilot's frames end at phases 0, 2,
// 5 and 7 ms, PX4's at 0, 2, 4, 6 and 8). The host's delays do
// not depend on the phase, so however busy the host (a CI host delayed receipts by 3.5 ms at p90;
// a container without CAP_SYS_NICE runs sitlnet's loop without SCHED_FIFO, 18 ms at p95), the
// two medians stay close. The test asserts they are within 2.5 ms.
TEST(RunTest, InRealtimePacingAutopilotsAreServedAtTheWallInstantOfTheirTime) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(
      14,
      "robot { name: \"ap\" position_m { x: 0 y: 0 z: 0.2 } image: \"test_autopilot\" "
      "ardupilot_json_port: 9002 args: [\"--json-port\", \"9002\", \"--rate-hz\", \"400\", "
      "\"--log-replies\"] }\n"
      "robot { name: \"px\" position_m { x: 0 y: 4 z: 0.2 } image: \"test_autopilot\" "
      "px4_sim_port: 4560 args: [\"--px4-port\", \"4560\", \"--log-replies\"] }\n",
      "timing { duration_ms: 3000 pacing: PACING_REALTIME }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* robot : {"ap", "px"}) {
    const ServedOnTime served = MeasureServedOnTime(ReadAll(out + "/robots/" + robot + ".log"));
    ASSERT_GT(served.observations, 500u) << robot;
    std::printf("%s\n", served.Describe(robot).c_str());
    ASSERT_GT(served.early_phase, 50u) << robot;
    ASSERT_GT(served.late_phase, 50u) << robot;
    EXPECT_LT(std::abs(served.phase_gap_ms), 2.5) << robot;
  }
  // summary.json's autopilot rates (docs/run.md, "Autopilot rates"). Oracles: each autopilot's
  // own log, one line per reply it took, so one per frame or actuator controls it answered with
  // (give or take the one in flight at the end); the rate its protocol asks for, ArduPilot's
  // --rate-hz and PX4's HIL_SENSOR every 4 ms. Served on time (above), each keeps that rate in
  // wall time, within what a busy host takes (the bound is loose: 80 %). Above the rate by at
  // most 5 %: a world late at the first answer serves the catch-up at once (60 ms late over the
  // run's 2.9 s is 2 %).
  const std::string summary = ReadAll(out + "/summary.json");
  for (const auto& [robot, nominal_hz] : {std::pair<std::string, double>{"ap", 400},
                                          std::pair<std::string, double>{"px", 250}}) {
    const std::string after = "\"name\":\"" + robot + "\"";
    const double replies = AutopilotReplies(ReadAll(out + "/robots/" + robot + ".log")).size();
    EXPECT_NEAR(SummaryNumber(summary, after, "\"autopilot_rate\":{\"answers\":"), replies, 2)
        << robot;
    EXPECT_EQ(SummaryNumber(summary, after, "\"nominal_hz\":"), nominal_hz) << robot;
    const double achieved_hz = SummaryNumber(summary, after, "\"achieved_hz\":");
    EXPECT_GT(achieved_hz, 0.8 * nominal_hz) << robot;
    EXPECT_LT(achieved_hz, 1.05 * nominal_hz) << robot;
    EXPECT_NEAR(SummaryNumber(summary, after, "\"ratio\":"), achieved_hz / nominal_hz, 1e-4)
        << robot;
  }
  EXPECT_EQ(SummaryNumber(summary, "\"autopilot_rates\":", "\"autopilots\":"), 2);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// Issue 14: an autopilot that stops answering (here it exits after 1 s of its clock) stops a
// lockstep run after the silent-robot timeout, naming it in its protocol's words, and nothing is
// left (the scenario's default on_silent_robot; SILENT_ROBOT_DROP cuts its motors instead, as
// for native robots). ArduPilot's protocol, then PX4's.
TEST(RunTest, ASilentAutopilotStopsTheLockstepRunNamingIt) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const struct {
    std::string port_field, args, message;
  } autopilots[] = {
      {"ardupilot_json_port: 9002", "\"--json-port\", \"9002\"",
       "robot 'ap' did not answer its JSON reply of iteration 100 (virtual 1000 ms) with a servo "
       "frame within 300 ms"},
      {"px4_sim_port: 4560", "\"--px4-port\", \"4560\"",
       "robot 'ap' did not answer its HIL_SENSOR of iteration 100 (virtual 1000 ms) with "
       "HIL_ACTUATOR_CONTROLS within 300 ms"},
  };
  for (const auto& autopilot : autopilots) {
    const RunScenario scenario = WriteScenario(
        12,
        "robot { name: \"ap\" position_m { x: 0 y: 0 z: 0.2 } image: \"test_autopilot\" " +
            autopilot.port_field + " args: [" + autopilot.args + ", \"--stop-after-s\", \"1\"] }\n",
        "timing { duration_ms: 5000 pacing: PACING_LOCKSTEP }\nsilent_robot_timeout_ms: 300\n");
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + "-out";
    const CommandResult result = SitlnetRun(scenario, out, {});
    EXPECT_EQ(result.exit_code, 1) << result.err;
    EXPECT_NE(result.err.find(autopilot.message), std::string::npos) << result.err;
    ExpectNothingLeft(scenario.name);
    RunCommand({"rm", "-rf", out});
  }
}

// Issue 14, item 5: an autopilot killed mid-run and started again, in lockstep pacing with
// on_silent_robot: SILENT_ROBOT_DROP. PX4 (the test autopilot, crashing once after 2 s of its
// clock, exit status 3) is dropped after the silent-robot timeout (motors cut), the image's
// restart policy starts it again, its new connection puts the robot back at its start and into
// the lock-step, and it answers again (how far it flies depends on the host: its first answers are
// not awaited).
TEST(RunTest, AKilledPx4IsDroppedAndARestartedOneFliesAgainFromTheStart) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string folder = TempDir() + "/crash_once";
  ASSERT_EQ(RunCommand({"mkdir", "-p", folder}).exit_code, 0);
  const std::string fly =
      "${SITLNET_BIN}/test_autopilot --px4-port 4560 --altitude-m 5 --log-replies";
  const std::string manifest = WriteImageManifest(
      "crashing_px4", "command: [\"/bin/sh\", \"-c\", \"if mkdir " + folder + "/crashed; then " +
                          fly + " --stop-after-s 2; exit 3; fi; exec " + fly +
                          "\"]\nfiles: \"${SITLNET_BIN}/test_autopilot\"\nwritable: \"" + folder +
                          "\"\nrestart: RESTART_ON_FAILURE\nmax_restarts: 1\n");
  const RunScenario scenario =
      WriteScenario(15,
                    "robot { name: \"px\" position_m { x: 0 y: 0 z: 0.2 } px4_sim_port: 4560 "
                    "image: \"" +
                        manifest + "\" }\n",
                    "timing { duration_ms: 600000 pacing: PACING_LOCKSTEP }\n"
                    "silent_robot_timeout_ms: 300\non_silent_robot: SILENT_ROBOT_DROP\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  // The second instance's replies: those after a gap (the timeout, the restart) in the log.
  using Replies = std::vector<std::pair<double, std::array<double, 3>>>;
  const auto second_instance = [](const Replies& replies) {
    size_t restart = 1;
    while (restart < replies.size() && replies[restart].first - replies[restart - 1].first < 0.1) {
      ++restart;
    }
    return restart;
  };
  // Until the second instance has answered twice. With the robot dropped, nothing holds the
  // lockstep clock back until the restarted one connects: a run of 8 s ended before its restart
  // had started in 1 of 6 runs here and once in CI (connections 1). The duration is a cap.
  const CommandResult result = SitlnetRunUntil(
      scenario, out,
      [&] {
        const auto replies = AutopilotReplies(ReadAll(out + "/robots/px.log"));
        return replies.size() >= second_instance(replies) + 2;
      },
      120 * kNsPerS);
  ASSERT_TRUE(result.exit_code == 130 || result.exit_code == 0) << result.exit_code << result.err;
  EXPECT_NE(result.err.find("robot 'px' did not answer its HIL_SENSOR of iteration 200 within "
                            "300 ms: dropped from the run, motors cut"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("restarting robot \"px\" (1 of at most 1)"), std::string::npos)
      << result.err;
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_NE(summary.find("\"px4\":{\"connections\":2,"), std::string::npos) << summary;
  // The flight log of both instances: the first stops at 2 s, the second starts later at the
  // clock's time, from the start pose, and climbs to 5 m again.
  const auto replies = AutopilotReplies(ReadAll(out + "/robots/px.log"));
  ASSERT_FALSE(replies.empty());
  // The second instance's first message: after a gap (the timeout, the restart) in the log.
  const size_t restart = second_instance(replies);
  ASSERT_LT(restart, replies.size()) << "no second instance in the log";
  EXPECT_NEAR(replies[restart - 1].first, 1.996, 1e-9);  // The first answered its last at 1.996 s.
  EXPECT_GT(replies[restart - 1].second[2], 1) << "the first instance had taken off";
  EXPECT_GT(replies[restart].first, 2.2);  // After the silent-robot timeout and the restart.
  EXPECT_NEAR(replies[restart].second[2], 0.2, 0.01) << "back at its start pose";
  // How far it flies again is the host's to say: a restarted PX4's first answers are not waited
  // for (docs/autopilots.md). It answers in lock-step from its first answer on.
  EXPECT_GT(replies.size() - restart, 1u) << "the second instance answered";
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out, folder, manifest});
}

// Issue 14, item 4 (issue 47: the relay is sitlnet run's own): a ground station node (no physics:
// it stays where it is) receives an autopilot's telemetry over the simulated radio, and the run
// relays it to a program on the host (here the test itself, a UDP socket in place of the GCS),
// with no route between the node and the host
// (NnsUpTest.ThreeRobotsHaveTheSpecifiedDevicesAddressesAndRoutes checks that a node has no
// default route, as every robot).
TEST(RunTest, AGroundStationRelaysTelemetryToTheHostWithoutARoute) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string wlan = WlanPrefix(13);
  const int host = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  ASSERT_GE(host, 0);
  sockaddr_in at{};
  at.sin_family = AF_INET;
  at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t at_size = sizeof at;
  ASSERT_EQ(bind(host, reinterpret_cast<const sockaddr*>(&at), sizeof at), 0)
      << std::strerror(errno);
  ASSERT_EQ(getsockname(host, reinterpret_cast<sockaddr*>(&at), &at_size), 0);
  const RunScenario scenario = WriteScenario(
      13,
      "robot { name: \"ap\" position_m { x: 0 y: 0 z: 0.2 } image: \"test_autopilot\" "
      "ardupilot_json_port: 9002 args: [\"--json-port\", \"9002\", \"--telemetry\", \"" +
          wlan + "2:14550\"] }\n" + "robot { name: \"gcs\" position_m { x: 20 y: 0 z: 2 } " +
          "ground_station: true }\n",
      "timing { duration_ms: 4000 pacing: PACING_REALTIME }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  // Read while the run goes on, as a GCS does.
  std::atomic<bool> run_over{false};
  std::vector<std::string> relayed;
  std::thread gcs([&] {
    char buffer[512];
    while (!run_over) {
      pollfd readable{host, POLLIN, 0};
      if (poll(&readable, 1, 100) != 1) continue;
      const ssize_t n = recv(host, buffer, sizeof buffer, 0);
      if (n > 0) relayed.emplace_back(buffer, n);
    }
  });
  const CommandResult result =
      SitlnetRun(scenario, out, {"--gcs", "udp:127.0.0.1:" + std::to_string(ntohs(at.sin_port))});
  run_over = true;
  gcs.join();
  close(host);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const std::string& datagram : relayed) {  // MAVLink 2, HEARTBEAT or GLOBAL_POSITION_INT
    ASSERT_GE(datagram.size(), 12u);
    EXPECT_EQ(static_cast<uint8_t>(datagram[0]), 0xFD);
    EXPECT_TRUE(datagram[7] == 0 || datagram[7] == 33) << static_cast<int>(datagram[7]);
  }
  // 10 Hz over the 3.5 s after arming, and 4 heartbeats (realtime pacing: a GCS is watched by
  // a person); the relay is bound before the images start.
  EXPECT_GE(relayed.size(), 39u) << result.err;
  EXPECT_GE(CapturedTimes(out, "udp.dstport == 14550 && ip.dst == " + wlan + "2").size(), 39u);
  // No physics: the node never moved (robot 1 in trajectories.csv).
  std::istringstream rows(ReadAll(out + "/trajectories.csv"));
  int rows_of_gcs = 0;
  for (std::string row; std::getline(rows, row);) {
    double t = 0, x = 0, y = 0, z = 0;
    int robot = -1;
    if (std::sscanf(row.c_str(), "%lf,%d,%lf,%lf,%lf", &t, &robot, &x, &y, &z) != 5 || robot != 1) {
      continue;
    }
    EXPECT_EQ(x, 20);
    EXPECT_EQ(y, 0);
    EXPECT_EQ(z, 2);
    ++rows_of_gcs;
  }
  EXPECT_GE(rows_of_gcs, 40);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

}  // namespace
}  // namespace sitlnet::nns::testing

// The real autopilots commanded over the simulated radio (issue 31, item 4; docs/autopilots.md,
// "Commanding a vehicle over the radio"): a ground station robot runs a node-mavlink GCS (an
// implementation sitlnet did not write) that reaches the vehicle only through wlan0 and the
// medium. The vehicle's MAVLink goes to the station's wlan0 address, set by the robot's args
// (ArduPilot: --serial0 udpclient:ADDR:14550; PX4: the px4 manifest's --gcs ADDR). Oracles: the
// truth in trajectories.csv, the MAVLink frames in medium.pcap as node-mavlink decodes them, and
// the medium's own record of what crossed it (deliveries.csv).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

// The station is robot 0 (listed first, so that its GCS listens before the vehicle boots: a
// datagram to a closed port would draw an ICMP error), the vehicle robot 1.
constexpr int kStation = 0;
constexpr int kVehicle = 1;

// Why this test cannot fly the autopilot of `variable` here, or "" when it can.
std::string Missing(const char* variable, const char* program) {
  const char* dir = std::getenv(variable);
  if (dir == nullptr || *dir == '\0') {
    return std::string(variable) + " is not set: point it at the autopilot's build folder "
           "(docs/autopilots.md, \"Flying your own ArduPilot or PX4\")";
  }
  if (!std::filesystem::exists(std::string(dir) + "/" + program)) {
    return std::string(variable) + "=" + dir + " holds no " + program;
  }
  return NodeMavlinkMissing();
}

#define SITLNET_REQUIRE_AUTOPILOT(variable, program)                             \
  do {                                                                           \
    SITLNET_REQUIRE_NNS_PRIVILEGES();                                            \
    if (const std::string missing = Missing(variable, program); !missing.empty()) { \
      if (IsCi()) FAIL() << missing;                                             \
      GTEST_SKIP() << missing;                                                   \
    }                                                                            \
  } while (0)

// A ground station robot's image: node-mavlink's GCS script `script` with `args`, ready once it
// printed `LISTENING` (bound to its UDP port).
std::string StationManifest(const std::string& script, const std::vector<std::string>& args) {
  std::string body = "command: \"node\"\ncommand: \"" + NodeMavlinkDir() + "/" + script + "\"\n";
  for (const std::string& arg : args) body += "command: \"" + arg + "\"\n";
  // Bound in also when the checkout lies under /tmp (the sandbox's /tmp is its own).
  body += "files: \"" + NodeMavlinkDir() + "\"\nready_log_line: \"LISTENING\"\n";
  return WriteImageManifest("station", body);
}

// One row of trajectories.csv: time and world ENU position.
struct Row {
  double t_s = 0;
  double x_m = 0, y_m = 0, z_m = 0;
};

std::vector<Row> RobotRows(const std::string& csv, int robot) {
  std::vector<Row> rows;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    Row row;
    int r = -1;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf,%lf", &row.t_s, &r, &row.x_m, &row.y_m,
                    &row.z_m) == 5 &&
        r == robot) {
      rows.push_back(row);
    }
  }
  return rows;
}

// The row at or just before `t_s` (rows every 100 ms).
const Row& RowAt(const std::vector<Row>& rows, double t_s) {
  size_t i = 0;
  while (i + 1 < rows.size() && rows[i + 1].t_s <= t_s + 1e-9) ++i;
  return rows.at(i);
}

// The MAVLink messages of the UDP datagrams from `from` to `to` in OUT/medium.pcap (first
// transmissions, no ICMP quoting them), decoded by node-mavlink (tests/node_mavlink/decode.cjs,
// CRC and CRC_EXTRA checked): message name -> count, and the COMMAND_LONG commands' ids -> count.
struct Crossed {
  std::map<std::string, int> messages;
  std::map<std::string, int> commands;
  std::string counts;  // "COUNTS valid=.. invalid=.. unknown=.."
  int Messages(const std::string& name) const {
    const auto it = messages.find(name);
    return it == messages.end() ? 0 : it->second;
  }
  int Commands(int id) const {
    const auto it = commands.find(std::to_string(id));
    return it == commands.end() ? 0 : it->second;
  }
};

Crossed DecodeCrossing(const std::string& out, const std::string& from, const std::string& to) {
  const CommandResult tshark = RunCommand(
      {"tshark", "-r", out + "/medium.pcap", "-Y",
       "udp && ip.src == " + from + " && ip.dst == " + to + " && wlan.fc.retry == 0 && !icmp",
       "-T", "fields", "-e", "data.data"},
      120 * kNsPerS);
  EXPECT_EQ(tshark.exit_code, 0) << tshark.err;
  std::string bytes;
  std::istringstream lines(tshark.out);
  for (std::string hex; std::getline(lines, hex);) {
    for (size_t i = 0; i + 1 < hex.size(); i += 2) {
      bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
  }
  const std::string stream = out + "/crossing.bin";
  std::ofstream(stream, std::ios::binary) << bytes;
  const CommandResult node = RunCommand(
      {"sh", "-c", "node \"$0/decode.cjs\" < \"$1\"", NodeMavlinkDir(), stream}, 120 * kNsPerS);
  EXPECT_EQ(node.exit_code, 0) << node.err;
  Crossed crossed;
  std::istringstream decoded(node.out);
  for (std::string line; std::getline(decoded, line);) {
    std::istringstream words(line);
    std::string kind, id, name;
    words >> kind >> id >> name;
    if (kind == "COUNTS") crossed.counts = line;
    if (kind != "MSG") continue;
    ++crossed.messages[name];
    for (std::string word; words >> word;) {
      if (name == "COMMAND_LONG" && word.rfind("command=", 0) == 0) ++crossed.commands[word.substr(8)];
    }
  }
  return crossed;
}

// Frames the medium delivered from robot `from` to robot `to` (deliveries.csv:
// time_ns,from,to,rx_power_dbm,sinr_db).
int Delivered(const std::string& out, int from, int to) {
  std::istringstream lines(ReadAll(out + "/deliveries.csv"));
  int n = 0;
  for (std::string line; std::getline(lines, line);) {
    long long t = 0;
    int f = -1, d = -1;
    if (std::sscanf(line.c_str(), "%lld,%d,%d", &t, &f, &d) == 3 && f == from && d == to) ++n;
  }
  return n;
}

// What a GCS script printed: "NAME t=<autopilot s>" events.
std::map<std::string, double> Events(const std::string& log) {
  std::map<std::string, double> events;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    char name[32];
    double t = 0;
    if (std::sscanf(line.c_str(), "%31[A-Z_] t=%lf", name, &t) == 2) events[name] = t;
  }
  return events;
}

// Issue 31, item 4, ArduCopter: the station sets GUIDED and arms (COMMAND_LONG DO_SET_MODE,
// COMPONENT_ARM_DISARM), takes off to 5 m (NAV_TAKEOFF), flies to 20 m north
// (SET_POSITION_TARGET_LOCAL_NED) and lands (DO_SET_MODE LAND), all over the medium, in
// lockstep pacing. ArduCopter's own oracle: it arms once its EKF uses GPS (about 42 s of its
// time, as with its own quad model, arducopter_flight_test.cc).
TEST(AutopilotRadioTest, AStationRobotFliesArduCopterOverTheMediumInLockstep) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_ARDUPILOT_DIR", "bin/arducopter");
  constexpr double kAltitudeM = 5, kHoldS = 2, kNorthM = 20;
  const std::string wlan = WlanPrefix(2);
  const std::string station = wlan + std::to_string(kStation + 1);
  const std::string vehicle = wlan + std::to_string(kVehicle + 1);
  const std::string manifest = StationManifest(
      "guided_flight.cjs", {"udpin", "14550", std::to_string(kAltitudeM), std::to_string(kHoldS),
                            std::to_string(kNorthM), "0"});
  const RunScenario scenario = WriteScenario(
      2,
      "robot { name: \"gcs\" position_m { x: 5 y: 10 z: 2 } ground_station: true image: \"" +
          manifest + "\" }\n" +
          "robot { name: \"c1\" position_m { x: 0 y: 0 z: 0.1 } ardupilot_json_port: 9002 "
          "image: \"arducopter\" args: [\"--serial0\", \"udpclient:" + station + ":14550\"] }\n",
      "timing { duration_ms: 80000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  const CommandResult run = SitlnetRun(scenario, out, {});
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string log = ReadAll(out + "/robots/gcs.log");
  const std::map<std::string, double> events = Events(log);
  for (const char* event : {"ARMED", "TAKEOFF_REACHED", "WAYPOINT_REACHED", "LAND", "DISARMED"}) {
    ASSERT_EQ(events.count(event), 1u) << event << "\n" << log;
  }
  EXPECT_LT(events.at("ARMED"), 45) << "ArduPilot's own quad model arms at 41.9 s";

  // The flight, against the truth: holds 5 m above where it armed, reaches the waypoint, lands.
  const std::vector<Row> rows = RobotRows(ReadAll(out + "/trajectories.csv"), kVehicle);
  ASSERT_FALSE(rows.empty());
  const Row& armed = RowAt(rows, events.at("ARMED"));
  double worst_altitude_m = 0;
  int held = 0;
  for (const Row& row : rows) {
    if (row.t_s < events.at("TAKEOFF_REACHED") + 1 || row.t_s >= events.at("LAND")) continue;
    worst_altitude_m = std::max(worst_altitude_m, std::fabs(row.z_m - armed.z_m - kAltitudeM));
    ++held;
  }
  EXPECT_GT(held, 20);
  EXPECT_LT(worst_altitude_m, 0.3);
  const Row& at_land = RowAt(rows, events.at("LAND"));
  const double waypoint_m = std::hypot(at_land.x_m - armed.x_m, at_land.y_m - armed.y_m - kNorthM);
  EXPECT_LT(waypoint_m, 1);
  EXPECT_NEAR(RowAt(rows, events.at("DISARMED")).z_m, armed.z_m, 0.05);

  // The commands and the telemetry crossed the medium, as MAVLink that node-mavlink decodes.
  const Crossed commands = DecodeCrossing(out, station, vehicle);
  EXPECT_NE(commands.counts.find(" invalid=0 "), std::string::npos) << commands.counts;
  EXPECT_GT(commands.Commands(176), 0) << "DO_SET_MODE";
  EXPECT_GT(commands.Commands(400), 0) << "COMPONENT_ARM_DISARM";
  EXPECT_GT(commands.Commands(22), 0) << "NAV_TAKEOFF";
  EXPECT_GT(commands.Messages("SET_POSITION_TARGET_LOCAL_NED"), 0);
  const Crossed telemetry = DecodeCrossing(out, vehicle, station);
  EXPECT_NE(telemetry.counts.find(" invalid=0 "), std::string::npos) << telemetry.counts;
  EXPECT_GT(telemetry.Messages("HEARTBEAT"), 60);
  EXPECT_GT(telemetry.Messages("GLOBAL_POSITION_INT"), 300);
  EXPECT_GT(telemetry.Messages("COMMAND_ACK"), 0);
  const int up = Delivered(out, kStation, kVehicle), down = Delivered(out, kVehicle, kStation);
  EXPECT_GT(up, 0);
  EXPECT_GT(down, 300);
  std::printf("[ measured ] ArduCopter over the medium: armed %.1f s, took off %.1f s, "
              "waypoint %.1f s, disarmed %.1f s (virtual); altitude off by %.3f m, waypoint by "
              "%.3f m; %d COMMAND_LONG, %d position targets, %d GLOBAL_POSITION_INT; frames "
              "delivered station->vehicle %d, vehicle->station %d; %.1f s wall\n",
              events.at("ARMED"), events.at("TAKEOFF_REACHED"), events.at("WAYPOINT_REACHED"),
              events.at("DISARMED"), worst_altitude_m, waypoint_m,
              commands.Messages("COMMAND_LONG"),
              commands.Messages("SET_POSITION_TARGET_LOCAL_NED"),
              telemetry.Messages("GLOBAL_POSITION_INT"), up, down, wall_s);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out, manifest});
}

}  // namespace
}  // namespace sitlnet::nns::testing

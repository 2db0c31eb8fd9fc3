// The real autopilots commanded over the simulated radio (issue 31, item 4; docs/autopilots.md,
// "Commanding a vehicle over the radio"): a ground station robot runs a node-mavlink GCS (an
// implementation sitlnet did not write) that reaches the vehicle only through wlan0 and the
// medium. The vehicle's MAVLink goes to the station's wlan0 address, set by the robot's args
// (ArduPilot: --serial0 udpclient:ADDR:14550; PX4: the px4 manifest's --gcs ADDR). Oracles: the
// truth in trajectories.csv, the MAVLink frames in medium.pcap as node-mavlink decodes them, and
// the medium's own record of what crossed it (deliveries.csv). Each flight flies in both pacings.
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

#include "tests/integration/mavlink_oracle.h"
#include "tests/integration/realtime_judge.h"
#include "tests/integration/run_test_util.h"
#include "view/air_modes.h"

namespace sitlnet::nns::testing {
namespace {


// The station is robot 0 (listed first, so that its GCS listens before the vehicle boots: a
// datagram to a closed port would draw an ICMP error), the vehicle robot 1.
constexpr int kStation = 0;
constexpr int kVehicle = 1;

// A ground station robot's image: node-mavlink's GCS script `script` with `args`, ready once it
// printed `LISTENING` (bound to its UDP port).
std::string StationManifest(const std::string& script, const std::vector<std::string>& args) {
  std::string body = "command: \"node\"\ncommand: \"" + NodeMavlinkDir() + "/" + script + "\"\n";
  for (const std::string& arg : args) body += "command: \"" + arg + "\"\n";
  // Bound in also when the checkout lies under /tmp (the sandbox's /tmp is its own).
  body += "files: \"" + NodeMavlinkDir() + "\"\nready_log_line: \"LISTENING\"\n";
  return WriteImageManifest("station", body);
}

using Row = TrajectoryRow;

// The UDP payloads between addresses `a` and `b` in OUT/medium.pcap: source -> bytes.
std::map<std::string, std::string> PayloadsBetween(const std::string& out, const std::string& a,
                                                   const std::string& b) {
  return UdpPayloads(out, "udp and host " + a + " and host " + b,
                     "(ip.src == " + a + " && ip.dst == " + b + ") || (ip.src == " + b +
                         " && ip.dst == " + a + ")",
                     "ip.src");
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

// The route both tests fly: 5 m up, 20 m north, down. The station stands mid-route: at
// sitlnet's default radio (54 Mb/s, path loss exponent 3) the link fails beyond about 25 m
// (measured: SINR 21 dB at 26 m, every frame lost), as a real Wi-Fi link at that rate would.
constexpr double kAltitudeM = 5;
constexpr double kNorthM = 20;
constexpr const char* kStationPose = "position_m { x: 5 y: 10 z: 2 }";

// The first STATUSTEXT the station printed in which ArduPilot says the host starved its loop
// in realtime pacing (realtime_judge.h), or "".
std::string LoopRateComplaint(const std::string& log) {
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("STATUSTEXT ", 0) == 0 && integration_test::ArduPilotSaysItsLoopIsSlow(line)) {
      return line;
    }
  }
  return "";
}

// Virtual seconds a run may last. The station's GCS acts on the wall clock, outside the
// lock-step, so the virtual instant the vehicle disarms depends on the host's speed (measured:
// ArduCopter at 72 s, PX4 at 50 s); the test stops the run then (below), well before this cap.
constexpr int kDurationCapMs = 150000;

// A run in `pacing` with a ground station robot "gcs" of image `manifest` and the vehicle robot
// `vehicle_block` (a robot block's fields after its name), and what came out of it.
struct RadioFlight {
  std::string station, vehicle;  // wlan0 addresses
  std::string out;
  std::string log;  // the station's
  std::map<std::string, FlightEvent> events;
  std::vector<Row> rows;  // the vehicle's truth
  double wall_s = 0;
};

// Issue 34, item 2: the vehicle's autopilot modes as `sitlnet view` reads them from medium.pcap
// (view/air_modes.h), named from the numbers the real autopilot sent, must be the modes its
// flight shows in trajectories.csv: `climb` halfway up the first climb, `cruise` at the fastest
// horizontal move between, `descent` halfway down the last descent. A HEARTBEAT comes every
// second; each of those moments is seconds into its mode.
void ExpectModesOfTheFlight(const RadioFlight& flight, const std::string& climb,
                            const std::string& cruise, const std::string& descent) {
  const std::vector<view::ModeChange> changes =
      view::ReadAirModes(flight.out + "/medium.pcap", kVehicle + 1);
  std::string heard;
  for (const view::ModeChange& change : changes) {
    if (change.robot == kVehicle)
      heard += " " + change.mode + "@" + std::to_string(change.time_ns / 1e9);
  }
  const auto mode_at = [&](double t_s) {
    std::string mode = "(none yet)";
    for (const view::ModeChange& change : changes) {
      if (change.robot == kVehicle && change.time_ns <= t_s * 1e9) mode = change.mode;
    }
    return mode;
  };
  const auto& rows = flight.rows;
  size_t up = 0, down = rows.size();
  while (up < rows.size() && rows[up].z_m < kAltitudeM / 2) ++up;
  while (down > up && rows[down - 1].z_m < kAltitudeM / 2) --down;
  ASSERT_LT(up + 1, down) << "the vehicle never flew above half its altitude";
  size_t fastest = up;
  double fastest_m = 0;
  for (size_t i = up + 1; i < down; ++i) {
    const double moved_m = std::hypot(rows[i].x_m - rows[i - 1].x_m, rows[i].y_m - rows[i - 1].y_m);
    if (moved_m > fastest_m) fastest = i, fastest_m = moved_m;
  }
  EXPECT_EQ(mode_at(rows[up].t_s), climb) << "at " << rows[up].t_s << " s; heard:" << heard;
  EXPECT_EQ(mode_at(rows[fastest].t_s), cruise)
      << "at " << rows[fastest].t_s << " s; heard:" << heard;
  EXPECT_EQ(mode_at(rows[down - 1].t_s), descent)
      << "at " << rows[down - 1].t_s << " s; heard:" << heard;
  std::printf(
      "[ measured ] the vehicle's modes over the air (at s):%s; climb %.1f s, cruise %.1f s, "
      "descent %.1f s\n",
      heard.c_str(), rows[up].t_s, rows[fastest].t_s, rows[down - 1].t_s);
}

// Flies it: once the station's log says DISARMED (both GCS scripts then exit), or
// `ends_on_loop_complaint` and ArduPilot said it missed its loop (a flight to fly once more), the
// run is stopped with SIGINT, in order, its outputs complete.
RadioFlight FlyOverTheMedium(int slot, const std::string& pacing, const std::string& manifest,
                             const std::string& vehicle_block, bool ends_on_loop_complaint = false) {
  RadioFlight flight;
  flight.station = WlanPrefix(slot) + std::to_string(kStation + 1);
  flight.vehicle = WlanPrefix(slot) + std::to_string(kVehicle + 1);
  const RunScenario scenario = WriteScenario(
      slot,
      std::string("robot { name: \"gcs\" ") + kStationPose + " ground_station: true image: \"" +
          manifest + "\" }\nrobot { name: \"v\" " + vehicle_block + " }\n",
      "timing { duration_ms: " + std::to_string(kDurationCapMs) + " pacing: " + pacing + " }\n");
  DownGuard guard(scenario.name);
  flight.out = TempDir() + "/" + scenario.name + "-out";
  RunCommand({"rm", "-rf", flight.out});  // a flight flown once more
  const std::string log = flight.out + "/robots/gcs.log";
  const auto start = std::chrono::steady_clock::now();
  // "DISARMED t=" (guided_flight_plan.cjs) or "EVENT DISARMED t_ms=" (px4_flight_plan.cjs).
  const auto done = [&] {
    const std::string text = ReadAll(log);
    return text.find("DISARMED t") != std::string::npos ||
           (ends_on_loop_complaint && !LoopRateComplaint(text).empty());
  };
  const CommandResult run =
      SitlnetRunUntil(scenario, flight.out, done, 2 * kDurationCapMs * kNsPerMs);
  flight.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(run.exit_code == 130 || run.exit_code == 0) << run.exit_code << " " << run.err;
  flight.log = ReadAll(log);
  flight.events = FlightEvents(flight.log);
  flight.rows = TrajectoryRows(ReadAll(flight.out + "/trajectories.csv"), kVehicle);
  EXPECT_FALSE(flight.rows.empty());
  ExpectNothingLeft(scenario.name);
  return flight;
}

// Whether the station saw every one of `events`, each once; says which not, with the host's load
// and the station's events.
bool SawEvents(const RadioFlight& flight, const std::vector<std::string>& events) {
  bool all = true;
  for (const std::string& event : events) {
    all = all && flight.events.count(event) == 1;
    EXPECT_EQ(flight.events.count(event), 1u)
        << event << "\n" << integration_test::HostLoad() << "\n"
        << integration_test::WithoutLines(flight.log, {"POS "});
  }
  return all;
}

// The truth of a flight: the largest altitude error above where it armed over [from_s, to_s),
// its distance to the waypoint at `arrived_s`, its height above the ground when it disarmed.
struct FlightErrors {
  double altitude_m = 0;
  int rows_held = 0;
  double waypoint_m = 0;
  double landed_m = 0;
};

FlightErrors Errors(const RadioFlight& flight, double armed_s, double from_s, double to_s,
                    double arrived_s, double disarmed_s) {
  FlightErrors errors;
  const Row& armed = RowAt(flight.rows, armed_s);
  for (const Row& row : flight.rows) {
    if (row.t_s < from_s || row.t_s >= to_s) continue;
    errors.altitude_m = std::max(errors.altitude_m, std::fabs(row.z_m - armed.z_m - kAltitudeM));
    ++errors.rows_held;
  }
  const Row& arrived = RowAt(flight.rows, arrived_s);
  errors.waypoint_m = std::hypot(arrived.x_m - armed.x_m, arrived.y_m - armed.y_m - kNorthM);
  errors.landed_m = RowAt(flight.rows, disarmed_s).z_m - armed.z_m;
  return errors;
}

// Both directions of a flight as they crossed the medium, decoded, with the checks every flight
// must pass: node-mavlink found no invalid frame either way; the vehicle's HEARTBEATs (1 Hz),
// GLOBAL_POSITION_INTs and COMMAND_ACKs reached the station; the medium delivered frames both
// ways (deliveries.csv).
struct Crossings {
  Crossed commands;   // station -> vehicle
  Crossed telemetry;  // vehicle -> station
};

Crossings ExpectCrossedBothWays(const RadioFlight& flight, int min_heartbeats, int min_positions) {
  std::map<std::string, std::string> payloads =
      PayloadsBetween(flight.out, flight.station, flight.vehicle);
  Crossings crossings{DecodeMavlink(payloads[flight.station], flight.out + "/commands.bin"),
                      DecodeMavlink(payloads[flight.vehicle], flight.out + "/telemetry.bin")};
  for (const Crossed* way : {&crossings.commands, &crossings.telemetry}) {
    EXPECT_NE(way->counts.find(" invalid=0 "), std::string::npos) << way->counts;
  }
  EXPECT_GT(crossings.telemetry.Messages("HEARTBEAT"), min_heartbeats);
  EXPECT_GT(crossings.telemetry.Messages("GLOBAL_POSITION_INT"), min_positions);
  EXPECT_GT(crossings.telemetry.Messages("COMMAND_ACK"), 0);
  EXPECT_GT(Delivered(flight.out, kStation, kVehicle), 0);
  EXPECT_GT(Delivered(flight.out, kVehicle, kStation), min_positions);
  return crossings;
}

// Frames the medium delivered each way, printed with the test's other measurements.
std::string CrossingSummary(const RadioFlight& flight) {
  return "frames delivered station->vehicle " +
         std::to_string(Delivered(flight.out, kStation, kVehicle)) + ", vehicle->station " +
         std::to_string(Delivered(flight.out, kVehicle, kStation));
}

// The ArduCopter flight of guided_flight.cjs (GUIDED, arm, take off, waypoint, land) and what
// crossed the medium, checked; `pacing` is printed with the measurements. ArduCopter's own
// oracles: it arms once its EKF uses GPS (about 42 s of its time, as with its own quad model,
// arducopter_flight_test.cc), and it does not say the host missed its loop.
void ExpectArduCopterFlight(const RadioFlight& flight, const std::string& pacing) {
  EXPECT_EQ(LoopRateComplaint(flight.log), "") << integration_test::HostLoad();
  const auto at = [&](const char* event) { return flight.events.at(event).t_s; };
  EXPECT_LT(at("ARMED"), 45) << "ArduPilot's own quad model arms at 41.9 s";
  // Held from 1 s after it reached the altitude until it was told to land; at the waypoint then.
  const FlightErrors errors = Errors(flight, at("ARMED"), at("TAKEOFF_REACHED") + 1, at("LAND"),
                                     at("LAND"), at("DISARMED"));
  EXPECT_GT(errors.rows_held, 20);
  EXPECT_LT(errors.altitude_m, 0.3) << integration_test::HostLoad() << "\n"
                                    << integration_test::WithoutLines(flight.log, {"POS "});
  EXPECT_LT(errors.waypoint_m, 1);
  EXPECT_NEAR(errors.landed_m, 0, 0.05);

  // The commands and the telemetry crossed the medium, as MAVLink that node-mavlink decodes.
  const auto [commands, telemetry] = ExpectCrossedBothWays(flight, 60, 300);
  EXPECT_GT(commands.Commands(176), 0) << "DO_SET_MODE";
  EXPECT_GT(commands.Commands(400), 0) << "COMPONENT_ARM_DISARM";
  EXPECT_GT(commands.Commands(22), 0) << "NAV_TAKEOFF";
  EXPECT_GT(commands.Messages("SET_POSITION_TARGET_LOCAL_NED"), 0);
  ExpectModesOfTheFlight(flight, "GUIDED", "GUIDED", "LAND");  // DO_SET_MODE GUIDED, then LAND
  std::printf(
      "[ measured ] ArduCopter over the medium, %s: armed %.1f s, took off %.1f s, waypoint %.1f s, "
      "disarmed %.1f s (virtual); altitude off by %.3f m, waypoint by %.3f m; %d "
      "COMMAND_LONG, %d position targets, %d GLOBAL_POSITION_INT; %s; %.1f s wall\n",
      pacing.c_str(), at("ARMED"), at("TAKEOFF_REACHED"), at("WAYPOINT_REACHED"), at("DISARMED"),
      errors.altitude_m, errors.waypoint_m, commands.Messages("COMMAND_LONG"),
      commands.Messages("SET_POSITION_TARGET_LOCAL_NED"), telemetry.Messages("GLOBAL_POSITION_INT"),
      CrossingSummary(flight).c_str(), flight.wall_s);
}

const std::vector<std::string> kGuidedFlightEvents = {"ARMED", "TAKEOFF_REACHED",
                                                      "WAYPOINT_REACHED", "LAND", "DISARMED"};

// The robot block of an ArduCopter whose GCS link goes to the station of `slot`.
std::string ArduCopterBlock(int slot) {
  return "position_m { x: 0 y: 0 z: 0.1 } ardupilot_json_port: 9002 image: \"arducopter\" "
         "args: [\"--serial0\", \"udpclient:" +
         WlanPrefix(slot) + std::to_string(kStation + 1) + ":14550\"]";
}

// guided_flight.cjs's arguments after its port: the route.
std::vector<std::string> GuidedRoute() {
  return {std::to_string(kAltitudeM), "2", std::to_string(kNorthM), "0"};
}

// Issue 31, item 4, ArduCopter: the station sets GUIDED and arms (COMMAND_LONG DO_SET_MODE,
// COMPONENT_ARM_DISARM), takes off (NAV_TAKEOFF), flies to the waypoint
// (SET_POSITION_TARGET_LOCAL_NED) and lands (DO_SET_MODE LAND), all over the medium, in `pacing`;
// ArduCopter's --serial0 udpclient sends to the station. Returns true, having checked nothing,
// when `may_fly_again` and ArduPilot said the host did not keep its loop in realtime pacing (the
// flight then ended at once; realtime_judge.h flies it once more).
bool FlyArduCopterOverTheMedium(const std::string& pacing, bool may_fly_again) {
  std::vector<std::string> args = {"udpin", "14550"};
  for (const std::string& arg : GuidedRoute()) args.push_back(arg);
  const std::string manifest = StationManifest("guided_flight.cjs", args);
  const bool may_end_early = pacing == "PACING_REALTIME" && may_fly_again;
  const RadioFlight flight =
      FlyOverTheMedium(2, pacing, manifest, ArduCopterBlock(2), may_end_early);
  const std::string complaint = LoopRateComplaint(flight.log);
  if (may_end_early && !complaint.empty()) {
    std::printf("ArduPilot said \"%s\"\n", complaint.c_str());
    return true;
  }
  if (::testing::Test::HasFailure() || !SawEvents(flight, kGuidedFlightEvents)) return false;
  ExpectArduCopterFlight(flight, pacing);
  RunCommand({"rm", "-rf", flight.out});
  return false;
}

// Measured: disarmed at 71.0-72.0 s virtual, the run 16-17 s of wall time, the test 19-21 s.
TEST(AutopilotRadioTest, AStationRobotFliesArduCopterOverTheMediumInLockstep) {
  SITLNET_REQUIRE_FLIGHT(ArduPilotMissing());
  FlyArduCopterOverTheMedium("PACING_LOCKSTEP", false);
}

// Measured: disarmed at 72.0 s virtual, the run 75 s of wall time, the test 79-82 s (one flight).
TEST(AutopilotRadioTest, AStationRobotFliesArduCopterOverTheMediumInRealtime) {
  SITLNET_REQUIRE_FLIGHT(ArduPilotMissing());
  integration_test::FlyJudgedOnAHostThatKeptUp(
      [](bool may_fly_again) { return FlyArduCopterOverTheMedium("PACING_REALTIME", may_fly_again); });
}

// Issue 31, item 4, the host GCS relay both ways: ShippedFleetScenariosTest flies the shipped
// fleets from a GCS on the host through `sitlnet run`'s own relay (`--gcs`, gcs_link/).

// Issue 31, item 4, PX4: the station (fly_px4.cjs) arms (COMMAND_LONG COMPONENT_ARM_DISARM),
// takes off (NAV_TAKEOFF), climbs and flies to the waypoint (COMMAND_INT DO_REPOSITION) and
// lands (NAV_LAND), all over the medium, in `pacing`; PX4's radio link is the px4
// manifest's `--gcs ADDR` (mavlink start -t ADDR), its system id the manifest's `--sysid 7`. Bounds
// as px4_flight_test.cc's: the hold within 0.3 m of the commanded altitude, the arrival within 1 m
// of the waypoint, over the steady windows fly_px4.cjs names.
void FlyPx4OverTheMedium(const std::string& pacing) {
  const int slot = 3;
  const std::string station = WlanPrefix(slot) + std::to_string(kStation + 1);
  const RadioFlight flight = FlyOverTheMedium(
      slot, pacing,
      StationManifest("fly_px4.cjs",
                      {std::to_string(kAltitudeM), std::to_string(kNorthM), "0", "300"}),
      "position_m { x: 0 y: 0 z: 0.2 } px4_sim_port: 4560 image: \"px4\" "
      "args: [\"--gcs\", \"" +
          station + "\", \"--sysid\", \"7\"]");
  if (::testing::Test::HasFailure() ||
      !SawEvents(flight, {"ARMED", "TAKEOFF", "HOLD", "WAYPOINT", "ARRIVED", "LAND", "DISARMED"})) {
    return;
  }
  const auto& events = flight.events;
  const FlightErrors hold =
      Errors(flight, events.at("ARMED").t_s, events.at("HOLD").since_s, events.at("HOLD").t_s,
             events.at("ARRIVED").t_s, events.at("DISARMED").t_s);
  const FlightErrors arrival =
      Errors(flight, events.at("ARMED").t_s, events.at("ARRIVED").since_s, events.at("ARRIVED").t_s,
             events.at("ARRIVED").since_s, events.at("DISARMED").t_s);
  EXPECT_GT(hold.rows_held, 20);
  EXPECT_LT(hold.altitude_m, 0.3) << integration_test::HostLoad();
  EXPECT_LT(arrival.waypoint_m, 1);
  EXPECT_LT(hold.waypoint_m, 1);
  EXPECT_LT(hold.landed_m, 0.1);
  const std::string px4_log = ReadAll(flight.out + "/robots/v.log");
  // The manifest's radio link (PX4's own line when it starts a MAVLink instance).
  EXPECT_NE(px4_log.find("mode: Normal, data rate: 40000 B/s on udp port 14556 remote port 14550"),
            std::string::npos)
      << px4_log;

  const auto [commands, telemetry] = ExpectCrossedBothWays(flight, 40, 200);
  EXPECT_GT(commands.Commands(400), 0) << "COMPONENT_ARM_DISARM";
  EXPECT_GT(commands.Commands(22), 0) << "NAV_TAKEOFF";
  EXPECT_GT(commands.Commands(21), 0) << "NAV_LAND";
  EXPECT_GT(commands.Messages("COMMAND_INT"), 0) << "DO_REPOSITION";
  EXPECT_GT(commands.Messages("HEARTBEAT"), 0);
  // NAV_TAKEOFF, DO_REPOSITION (PX4's Hold), NAV_LAND: PX4's Takeoff, Hold and Land modes.
  ExpectModesOfTheFlight(flight, "AUTO.TAKEOFF", "AUTO.LOITER", "AUTO.LAND");
  // The manifest's --sysid: every message PX4 sent over the radio carries it.
  EXPECT_EQ(telemetry.systems.size(), 1u);
  EXPECT_GT(telemetry.systems.count("7"), 0u);
  std::printf(
      "[ measured ] PX4 over the medium, %s: armed %.1f s, hold to %.1f s, arrived %.1f s, "
      "disarmed %.1f s (virtual); altitude off by %.3f m, waypoint by %.3f m; %d "
      "COMMAND_LONG, %d COMMAND_INT, %d GLOBAL_POSITION_INT; %s; %.1f s wall\n",
      pacing.c_str(), events.at("ARMED").t_s, events.at("HOLD").t_s, events.at("ARRIVED").t_s,
      events.at("DISARMED").t_s, hold.altitude_m, arrival.waypoint_m,
      commands.Messages("COMMAND_LONG"), commands.Messages("COMMAND_INT"),
      telemetry.Messages("GLOBAL_POSITION_INT"), CrossingSummary(flight).c_str(), flight.wall_s);
  RunCommand({"rm", "-rf", flight.out});
}

// Measured: disarmed at 49.8-51.1 s virtual, the run 6-8 s of wall time, the test 8-9 s.
TEST(AutopilotRadioTest, AStationRobotFliesPx4OverTheMediumInLockstep) {
  SITLNET_REQUIRE_FLIGHT(Px4Missing());
  FlyPx4OverTheMedium("PACING_LOCKSTEP");
}

// Measured: disarmed at 49.6-50.1 s virtual, the run 50-51 s of wall time, the test 53 s.
TEST(AutopilotRadioTest, AStationRobotFliesPx4OverTheMediumInRealtime) {
  SITLNET_REQUIRE_FLIGHT(Px4Missing());
  integration_test::FlyJudgedOnAHostThatKeptUp([](bool) {
    FlyPx4OverTheMedium("PACING_REALTIME");
    return false;
  });
}

}  // namespace
}  // namespace sitlnet::nns::testing

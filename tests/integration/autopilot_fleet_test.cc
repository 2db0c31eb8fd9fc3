// A fleet of real autopilots in one lockstep run (issue 31, item 5): PX4 v1.14.4 and ArduCopter
// SITL robots, and a ground station robot (tests/node_mavlink/fleet_lockstep.cjs, node-mavlink)
// that commands every one of them over wlan0 and the medium, telling them apart by their MAVLink
// system ids (the manifests' --sysid). The formation mission: every vehicle takes off, flies the
// same four waypoints from its own home, and lands. Oracle: the truth in trajectories.csv.
// 4 PX4 + 4 ArduCopter (SITLNET_FLEET_EACH=N flies N of each instead; docs/performance.md,
// "The real autopilots").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "tests/integration/mavlink_oracle.h"
#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::ReadAll;
using integration_test::TempDir;

// How many vehicles of each kind: SITLNET_FLEET_EACH, else 4. Up to 4: beyond, the formation
// outgrows the radio's range from the station.
int EachKind() {
  const char* each = std::getenv("SITLNET_FLEET_EACH");
  return each != nullptr && std::atoi(each) > 0 ? std::atoi(each) : 4;
}
constexpr double kAltitudeM = 5;
constexpr double kSpacingM = 3;  // between neighbours of the formation
// The route from each vehicle's home: a 4 m square, north then east (fleet_lockstep.cjs's ROUTE).
struct Waypoint {
  double north_m, east_m;
};
constexpr Waypoint kRoute[] = {{4, 0}, {4, 4}, {0, 4}, {0, 0}};
constexpr const char* kRouteArg = "4,0/4,4/0,4/0,0";
// The run may last up to this; the test stops it once every vehicle has disarmed (measured:
// 77.3 s). ArduCopter arms once its EKF uses GPS, about 42 s of its clock
// (arducopter_flight_test.cc); then about 35 s of flight (take-off, four legs with a 1 s hold at
// each, landing).
constexpr int kDurationCapMs = 150000;

// The first row at or after `from` where the vehicle is within 1 m of `target` (x east, y north,
// z up, world metres), or rows.size().
size_t FirstWithin1M(const std::vector<TrajectoryRow>& rows, size_t from, double x_m, double y_m,
                     double z_m, double* closest_m) {
  for (size_t i = from; i < rows.size(); ++i) {
    const double off_m = std::hypot(rows[i].x_m - x_m, rows[i].y_m - y_m, rows[i].z_m - z_m);
    *closest_m = std::min(*closest_m, off_m);
    if (off_m <= 1) return i;
  }
  return rows.size();
}

// Robot 0 is the station (listed first, so that it listens before the vehicles boot), robots 1..
// the PX4s then the ArduCopters, each with system id = its robot index, on a grid of two rows
// `kSpacingM` apart; the station (a robot of the lock-step, on the ground: its motors stay off)
// stands south of them, within 15 m of every waypoint (the
// default 54 Mb/s radio loses its links beyond about 25 m).
TEST(AutopilotFleetTest, EveryVehicleOfAMixedFleetReachesEveryWaypointWithin1M) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(Px4Missing());
  SITLNET_REQUIRE(ArduPilotMissing());
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const int slot = 12;
  const std::string station = WlanPrefix(slot) + "1";
  const int px4s = EachKind();
  const int vehicles = 2 * px4s;
  const int per_row = (vehicles + 1) / 2;
  std::vector<std::string> station_args = {std::to_string(kAltitudeM), "1", kRouteArg};
  std::string robots = "robot { name: \"gcs\" position_m { x: 3 y: -3 z: 0.1 } image: \"" +
                       std::string("@STATION@") + "\" }\n";
  for (int id = 1; id <= vehicles; ++id) {
    const bool px4 = id <= px4s;
    const double x_m = kSpacingM * ((id - 1) % per_row), y_m = kSpacingM * ((id - 1) / per_row);
    char position[96];
    std::snprintf(position, sizeof position, "position_m { x: %.1f y: %.1f z: %.1f }", x_m, y_m,
                  px4 ? 0.2 : 0.1);
    const std::string sysid = std::to_string(id);
    const std::string lean = LeanAutopilots() ? "\"--lean\", " : "";
    robots += "robot { name: \"v" + sysid + "\" " + position +
              (px4 ? " px4_sim_port: 4560 image: \"px4\" args: [" + lean + "\"--gcs\", \"" +
                         station + "\", \"--sysid\", \"" + sysid + "\"] }\n"
                   : " ardupilot_json_port: 9002 image: \"arducopter\" args: [" + lean +
                         "\"--serial0\", "
                         "\"udpclient:" +
                         station + ":14550\", \"--sysid\", \"" + sysid + "\"] }\n");
    station_args.push_back((px4 ? "px4:" : "arducopter:") + sysid);
  }
  robots.replace(robots.find("@STATION@"), 9,
                 WriteStationImage("fleet_lockstep.cjs", station_args));
  const RunScenario scenario = WriteScenario(
      slot, robots,
      "timing { duration_ms: " + std::to_string(kDurationCapMs) + " pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  // Each vehicle's "sys=N DISARMED t=" (ArduCopter) or "sys=N EVENT DISARMED t_ms=" (PX4).
  const auto disarmed = [&] {
    const std::string log = ReadAll(out + "/robots/gcs.log");
    int seen = 0;
    for (size_t at = log.find("DISARMED t"); at != std::string::npos;
         at = log.find("DISARMED t", at + 1)) {
      ++seen;
    }
    return seen;
  };
  const CommandResult run = SitlnetRunUntil(
      scenario, out, [&] { return disarmed() == vehicles; }, 2 * kDurationCapMs * kNsPerMs);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(run.exit_code == 130 || run.exit_code == 0) << run.exit_code << " " << run.err;
  const std::string log = ReadAll(out + "/robots/gcs.log");
  const std::string csv = ReadAll(out + "/trajectories.csv");
  double run_s = 0;  // virtual seconds the run lasted
  for (int id = 1; id <= vehicles; ++id) {
    const bool px4 = id <= px4s;
    const std::string who = std::string(px4 ? "PX4" : "ArduCopter") + " sys=" + std::to_string(id);
    // The station saw it through: the last waypoint, then the disarm after landing.
    const std::string prefix = "sys=" + std::to_string(id) + " ";
    EXPECT_NE(log.find(prefix + (px4 ? "EVENT ARRIVED" : "WAYPOINT_REACHED")), std::string::npos)
        << who << "\n"
        << log.substr(0, 4000);
    EXPECT_NE(log.find(prefix + (px4 ? "EVENT DISARMED" : "DISARMED")), std::string::npos) << who;
    // The truth: from its home (where it stood at 3 s, before any vehicle arms), each waypoint in
    // turn at the commanded altitude, within 1 m; back on the ground at the end.
    const std::vector<TrajectoryRow> rows = TrajectoryRows(csv, id);
    ASSERT_GT(rows.size(), 30u) << who;
    const TrajectoryRow home = rows[30];
    size_t at = 0;
    std::string measured;
    for (const Waypoint& waypoint : kRoute) {
      double closest_m = 1e9;
      at = FirstWithin1M(rows, at, home.x_m + waypoint.east_m, home.y_m + waypoint.north_m,
                         home.z_m + kAltitudeM, &closest_m);
      EXPECT_LT(at, rows.size()) << who << ": waypoint " << waypoint.north_m << " N "
                                 << waypoint.east_m << " E never within 1 m (closest " << closest_m
                                 << " m)";
      if (at == rows.size()) break;
      char reached[64];
      std::snprintf(reached, sizeof reached, " %.1f s", rows[at].t_s);
      measured += reached;
    }
    EXPECT_LT(rows.back().z_m - home.z_m, 0.1) << who << " landed";
    const std::map<std::string, FlightEvent> events = FlightEvents(log, prefix);
    std::printf("[ measured ] %s: waypoints within 1 m at%s, disarmed at %.1f s (virtual)\n",
                who.c_str(), measured.c_str(),
                events.count("DISARMED") == 1 ? events.at("DISARMED").t_s : -1.0);
    run_s = rows.back().t_s;
  }
  std::printf("[ measured ] %d PX4 + %d ArduCopter, %.1f s virtual in %.1f s wall\n", px4s, px4s,
              run_s, wall_s);
  RunCommand({"rm", "-rf", out});
  ExpectNothingLeft(scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing

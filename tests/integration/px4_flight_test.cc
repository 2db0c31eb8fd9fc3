// The real PX4 v1.14 flies in `sitlnet run` (issue 31, items 1 and 2; docs/autopilots.md): one
// robot started through the shipped manifest robot_images/px4, PX4 found through
// SITLNET_PX4_DIR, commanded over its own GCS MAVLink link by node-mavlink
// (tests/node_mavlink/fly_px4.cjs), in both pacings. The oracle is PX4 itself (what its log
// says, where it says it is) and the truth sitlnet writes (trajectories.csv).
#include <sched.h>
#include <signal.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/integration/realtime_judge.h"
#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

constexpr double kAltitudeM = 5;    // take-off altitude above home
constexpr double kNorthM = 50;      // the waypoint, from home
// Virtual seconds the run may last: PX4 disarms at 54-64 s, and the test stops the run then.
constexpr double kDurationS = 150;
constexpr double kEarthRadiusM = 6371000;  // PX4's map projection (and fly_px4.cjs's)

// One row of trajectories.csv: time and the robot's position on Earth.
struct Truth {
  double t_s = 0;
  double x_m = 0, y_m = 0, z_m = 0;  // world ENU
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;
};

std::vector<Truth> ReadTruth(const std::string& csv) {
  std::vector<Truth> rows;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    Truth r;
    int robot = -1;
    double skip[7];
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf",
                    &r.t_s, &robot, &r.x_m, &r.y_m, &r.z_m, &skip[0], &skip[1], &skip[2],
                    &skip[3], &skip[4], &skip[5], &skip[6], &r.latitude_deg, &r.longitude_deg,
                    &r.altitude_m) == 15 &&
        robot == 0) {
      rows.push_back(r);
    }
  }
  return rows;
}

// The truth at `t_s`, linear between the 100 ms rows (at most 5 mm off at 3 m/s^2).
Truth TruthAt(const std::vector<Truth>& rows, double t_s) {
  const auto after = std::lower_bound(rows.begin(), rows.end(), t_s,
                                      [](const Truth& r, double t) { return r.t_s < t; });
  if (after == rows.begin()) return rows.front();
  if (after == rows.end()) return rows.back();
  const Truth& a = *(after - 1);
  const Truth& b = *after;
  const double f = (t_s - a.t_s) / (b.t_s - a.t_s);
  const auto mix = [f](double u, double v) { return u + f * (v - u); };
  return {t_s,
          mix(a.x_m, b.x_m),
          mix(a.y_m, b.y_m),
          mix(a.z_m, b.z_m),
          mix(a.latitude_deg, b.latitude_deg),
          mix(a.longitude_deg, b.longitude_deg),
          mix(a.altitude_m, b.altitude_m)};
}

// What fly_px4.cjs printed: events (PX4's time, ms), PX4's estimates (ODOMETRY: local NED from
// the estimator's origin, at the instant estimated) and that origin.
struct Flight {
  std::map<std::string, std::pair<long, long>> events;  // name -> (t_ms, since_ms or -1)
  std::vector<std::array<double, 4>> estimates;          // t_s, north_m, east_m, down_m
  std::optional<std::array<double, 3>> origin;           // lat_deg, lon_deg, alt_m
};

Flight ReadFlight(const std::string& out) {
  Flight flight;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    char name[32];
    long t = 0, since = -1, lat = 0, lon = 0, alt = 0;
    double north = 0, east = 0, down = 0;
    if (std::sscanf(line.c_str(), "EVENT %31s t_ms=%ld since_ms=%ld", name, &t, &since) >= 2) {
      flight.events[name] = {t, since};
    } else if (std::sscanf(line.c_str(), "ODOM t_us=%ld x=%lf y=%lf z=%lf", &t, &north, &east,
                           &down) == 4) {
      flight.estimates.push_back({t / 1e6, north, east, down});
    } else if (std::sscanf(line.c_str(), "ORIGIN lat=%ld lon=%ld alt=%ld", &lat, &lon, &alt) == 3) {
      flight.origin = {lat / 1e7, lon / 1e7, alt / 1e3};
    }
  }
  return flight;
}

// Horizontal distance (m) between two points on PX4's sphere, small separations.
double HorizontalM(double lat1, double lon1, double lat2, double lon2) {
  const double rad = M_PI / 180;
  const double north = (lat1 - lat2) * rad * kEarthRadiusM;
  const double east = (lon1 - lon2) * rad * kEarthRadiusM * std::cos(lat1 * rad);
  return std::hypot(north, east);
}

// Lines of PX4's log (or of the commander's STATUSTEXTs) that report a fault. One is PX4's
// own: its commander checks the estimator before its startup script has started ekf2, and may
// say "Preflight Fail: ekf2 missing data" once (it does with Gazebo too: the boot log in
// PX4-Autopilot pull request 21815, Gazebo classic's iris). That line is allowed before
// `boot_done` (a line that starts the flight part of the log), never after it.
std::vector<std::string> Complaints(const std::string& log, const std::string& boot_done) {
  std::vector<std::string> found;
  bool booting = true;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.find(boot_done) != std::string::npos) booting = false;
    if (booting && line.find("Preflight Fail: ekf2 missing data") != std::string::npos) continue;
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    for (const char* word : {"stale", "preflight fail", "failsafe", "arming denied"}) {
      if (lower.find(word) != std::string::npos) found.push_back(line);
    }
  }
  return found;
}

// PX4 v1.14.4's HRT thread runs every module's timer and sleeps in PX4's lockstep clock. The
// SIGCONT that should wake it for a sooner timer does not end a wait on a condition variable
// (hrt_queue.c, drv_hrt.cpp, lockstep_scheduler.cpp). A thread that re-arms a timer cancels the
// HRT's work item, then queues it again (hrt_call_reschedule). If that thread is preempted
// between the two and the HRT thread scans its queue meanwhile, the HRT thread sees no work and
// sleeps one second of PX4's clock; the battery simulator misses its turns, and after 5 s
// without a battery_status PX4 says "Preflight Fail: Battery unhealthy" (batteryCheck.cpp).
// Without CAP_SYS_NICE PX4's threads silently fell back to normal scheduling (tasks.cpp), so any
// thread of the host could preempt them there: 3 of 50 lockstep flights starved idle, 5 of 50
// beside two busy loops. The shipped manifest now keeps CAP_SYS_NICE, and PX4's threads run at
// the SCHED_FIFO priorities PX4 asks for: 0 of 50 in both (docs/autopilots-evidence.md, "PX4's
// HRT thread in lockstep"). A lockstep flight is flown once; a realtime one may still be flown
// again on a loaded host (below).
bool Px4SaysItsTimersStalled(const std::string& log) {
  return log.find("Battery unhealthy") != std::string::npos;
}

// The scheduling policy of PX4's HRT thread ("wkr_hrt", hrt_thread.c), seen from the host, or -1
// when no such thread runs in `netns`.
int HrtThreadPolicy(const std::string& netns) {
  std::istringstream pids(RunCommand({"ip", "netns", "pids", netns}).out);
  for (pid_t pid; pids >> pid;) {
    if (ReadAll("/proc/" + std::to_string(pid) + "/comm") != "px4\n") continue;
    std::error_code error;
    for (const auto& task :
         std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task", error)) {
      if (ReadAll(task.path().string() + "/comm") != "wkr_hrt\n") continue;
      return sched_getscheduler(static_cast<pid_t>(std::stol(task.path().filename().string())));
    }
  }
  return -1;
}

// Flies PX4 and checks the flight; sets `*starved` instead when `may_fly_again` (realtime
// pacing only) and PX4's own timers stalled (above): that flight is then flown once more.
// `lean`: the manifest's lean profile (also under SITLNET_TEST_AUTOPILOT_PROFILE=lean).
void FlyPx4(int slot, const char* pacing, bool may_fly_again, bool* starved, bool lean = false) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(Px4Missing());
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const RunScenario scenario = WriteScenario(
      slot,
      std::string("robot { name: \"px\" position_m { x: 3 y: -2 z: 0.2 } image: \"px4\" "
                  "px4_sim_port: 4560") +
          // Lean: PX4's own GCS link is off; the manifest's --gcs link to the robot's own
          // localhost takes its place (fly_px4.cjs listens there on 14550).
          (lean || LeanAutopilots() ? " args: [\"--lean\", \"--gcs\", \"127.0.0.1\"]" : "") +
          " }\n",
      "timing { duration_ms: " + std::to_string(static_cast<int>(kDurationS * 1000)) +
          " pacing: " + pacing + " }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  RunCommand({"rm", "-rf", out});  // A flight flown once more starts from nothing.
  const auto start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  // The commander enters the robot's namespace once it exists; PX4's GCS link answers it there.
  const std::string netns = scenario.name + "-px";
  ASSERT_TRUE(WaitForFiles(kNetnsDir, [&] { return NetnsExists(netns); }, 60 * kNsPerS))
      << run.err();
  CommandResult fly = RunCommand(
      {SitlnetBinary(), "exec", "--scenario", scenario.name, "px", "--", "node",
       integration_test::SourceDir() + "/tests/node_mavlink/fly_px4.cjs", std::to_string(kAltitudeM),
       std::to_string(kNorthM), "0", "300", "estimates"},
      320 * kNsPerS);
  // PX4 got the priorities it asked for (the manifest's CAP_SYS_NICE): without them its HRT
  // thread can be starved (Px4SaysItsTimersStalled). Read while PX4 still runs.
  const int hrt_policy = HrtThreadPolicy(netns);
  // The flight is over (or failed): the run stops in order, its outputs complete. The GCS acts
  // on the wall clock, outside the lock-step, so when PX4 disarms in virtual time depends on the
  // host's speed; a fixed duration could end the run before.
  kill(run.pid(), SIGINT);
  const int run_exit = run.Wait(60 * kNsPerS);
  ASSERT_TRUE(run_exit == 130 || run_exit == 0) << run_exit << " " << run.err();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string log = ReadAll(out + "/robots/px.log");
  if (may_fly_again && Px4SaysItsTimersStalled(log)) {
    std::printf("PX4's timers stalled (\"Battery unhealthy\"; px4_flight_test.cc says why)\n");
    *starved = true;
    ExpectNothingLeft(scenario.name);
    RunCommand({"rm", "-rf", out});
    return;
  }
  ASSERT_EQ(fly.exit_code, 0) << integration_test::HostLoad() << "\n"
                              << integration_test::WithoutLines(fly.out, {"POS ", "ODOM "}) << fly.err;

  EXPECT_EQ(hrt_policy, SCHED_FIFO)
      << "PX4's HRT thread runs with scheduling policy " << hrt_policy
      << " (-1: not found), not SCHED_FIFO: the robot's confinement refused PX4's priorities "
         "(CAP_SYS_NICE, or a cgroup without realtime runtime)";
  EXPECT_NE(log.find("Ready for takeoff"), std::string::npos) << log;
  EXPECT_EQ(Complaints(log, "Startup script returned successfully"), std::vector<std::string>{})
      << log;
  EXPECT_EQ(Complaints(fly.out, "POS "), std::vector<std::string>{})
      << integration_test::WithoutLines(fly.out, {"POS ", "ODOM "});

  const Flight flight = ReadFlight(fly.out);
  const std::vector<Truth> truth = ReadTruth(ReadAll(out + "/trajectories.csv"));
  ASSERT_FALSE(truth.empty());
  for (const char* event : {"ARMED", "TAKEOFF", "HOLD", "WAYPOINT", "ARRIVED", "LAND", "DISARMED"}) {
    ASSERT_EQ(flight.events.count(event), 1u)
        << event << "\n" << integration_test::WithoutLines(fly.out, {"POS ", "ODOM "});
  }
  const Truth home = TruthAt(truth, flight.events.at("ARMED").first / 1e3);

  // Altitude: the truth above home over PX4's hold, within 0.3 m of the commanded altitude.
  const auto [hold_end_ms, hold_start_ms] = flight.events.at("HOLD");
  double worst_altitude_m = 0;
  for (const Truth& row : truth) {
    if (row.t_s * 1e3 < hold_start_ms || row.t_s * 1e3 > hold_end_ms) continue;
    worst_altitude_m =
        std::max(worst_altitude_m, std::abs(row.altitude_m - home.altitude_m - kAltitudeM));
  }
  EXPECT_LT(worst_altitude_m, 0.3);

  // The waypoint: 50 m north of home (world +y), reached within 1 m, over PX4's steady arrival.
  const auto [arrived_end_ms, arrived_start_ms] = flight.events.at("ARRIVED");
  double worst_waypoint_m = 0;
  for (const Truth& row : truth) {
    if (row.t_s * 1e3 < arrived_start_ms || row.t_s * 1e3 > arrived_end_ms) continue;
    worst_waypoint_m = std::max(
        worst_waypoint_m, std::hypot(row.x_m - home.x_m, row.y_m - home.y_m - kNorthM));
  }
  EXPECT_LT(worst_waypoint_m, 1.0);

  // PX4's own estimate against the truth at the instant it estimates, from arming to disarming.
  // ODOMETRY, not GLOBAL_POSITION_INT: the latter is stamped when ekf2 published it, which a busy
  // host delays (10 ms at 5 m/s is 5 cm). Local NED to latitude and longitude: PX4's azimuthal
  // equidistant projection, which a plane matches to micrometres within 100 m of the origin.
  ASSERT_TRUE(flight.origin.has_value()) << integration_test::WithoutLines(fly.out, {"POS ", "ODOM "});
  const auto [origin_lat_deg, origin_lon_deg, origin_alt_m] = *flight.origin;
  double worst_horizontal_m = 0, worst_vertical_m = 0;
  int compared = 0;
  for (const auto& [t_s, north_m, east_m, down_m] : flight.estimates) {
    if (t_s * 1e3 < flight.events.at("ARMED").first ||
        t_s * 1e3 > flight.events.at("DISARMED").first || t_s > truth.back().t_s) {
      continue;
    }
    const Truth at = TruthAt(truth, t_s);
    const double rad = M_PI / 180;
    const double lat_deg = origin_lat_deg + north_m / kEarthRadiusM / rad;
    const double lon_deg =
        origin_lon_deg + east_m / (kEarthRadiusM * std::cos(origin_lat_deg * rad)) / rad;
    worst_horizontal_m = std::max(worst_horizontal_m,
                                  HorizontalM(lat_deg, lon_deg, at.latitude_deg, at.longitude_deg));
    worst_vertical_m = std::max(worst_vertical_m, std::abs(origin_alt_m - down_m - at.altitude_m));
    ++compared;
  }
  EXPECT_GT(compared, 500);
  EXPECT_LT(worst_horizontal_m, 0.3) << integration_test::HostLoad();
  EXPECT_LT(worst_vertical_m, 0.3);

  // Landed where it flew to, on the ground, disarmed before the run ended.
  const Truth landed = TruthAt(truth, flight.events.at("DISARMED").first / 1e3);
  EXPECT_LT(landed.z_m - home.z_m, 0.1);
  EXPECT_LT(std::hypot(landed.x_m - home.x_m, landed.y_m - home.y_m - kNorthM), 1.0);
  std::printf("[ measured ] %s: altitude error %.3f m, waypoint error %.3f m, estimate error "
              "%.3f m horizontal %.3f m vertical (%d reports), disarmed at %.1f s virtual, "
              "%.1f s wall\n",
              pacing, worst_altitude_m, worst_waypoint_m, worst_horizontal_m, worst_vertical_m,
              compared, flight.events.at("DISARMED").first / 1e3, wall_s);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// Flown once: the run waits for PX4, so neither the host's load nor PX4's timers excuse a
// failure (Px4SaysItsTimersStalled).
TEST(Px4FlightTest, InLockstepPacingPx4TakesOffHoldsFliesToAWaypointAndLands) {
  bool starved = false;
  FlyPx4(0, "PACING_LOCKSTEP", false, &starved);
}

// The lean profile (docs/autopilots.md): no MAVLink links of PX4's own, no logger; the same
// flight and oracles, commanded over the manifest's --gcs link instead. About 20 s of wall time.
TEST(Px4FlightTest, InLockstepPacingTheLeanProfileFliesTheSameFlight) {
  bool starved = false;
  FlyPx4(2, "PACING_LOCKSTEP", false, &starved, /*lean=*/true);
}

TEST(Px4FlightTest, InRealtimePacingPx4TakesOffHoldsFliesToAWaypointAndLands) {
  integration_test::FlyJudgedOnAHostThatKeptUp([](bool may_fly_again) {
    bool starved = false;
    FlyPx4(1, "PACING_REALTIME", may_fly_again, &starved);
    return starved;
  });
}

}  // namespace
}  // namespace sitlnet::nns::testing

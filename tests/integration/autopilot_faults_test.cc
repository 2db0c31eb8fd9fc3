// Faults with the real autopilots (issue 31, item 7 and "Bad input and limits"; docs/autopilots.md,
// "When an autopilot dies"): PX4 v1.14 and ArduCopter SITL killed with SIGKILL mid-flight in
// lockstep pacing, under each on_silent_robot policy; restarted by the image's restart policy, they
// reconnect and fly again; a PX4 that never connects, a wrong autopilot folder, a file that is no
// program and an autopilot that exits at boot are each refused in one line naming the robot and
// the cause, with a non-zero exit and nothing left. The autopilots run through the shipped
// manifests (robot_images/px4, robot_images/arducopter; the restart tests add the restart policy
// to a copy of the shipped text), found through SITLNET_PX4_DIR and SITLNET_ARDUPILOT_DIR, and
// are commanded by node-mavlink (tests/node_mavlink). Oracles: the autopilots' own reports (armed,
// at altitude), the truth in trajectories.csv, what the run prints and summary.json.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::Child;
using integration_test::ReadAll;
using integration_test::SitlnetBinary;
using integration_test::SourceDir;
using integration_test::TempDir;
using integration_test::WaitForFiles;

// Skips (fails under CI=true) when root, the autopilot of `why_missing` or (if it `flies`)
// node-mavlink is missing.
#define SITLNET_REQUIRE_AUTOPILOT(why_missing, flies)  \
  do {                                                 \
    SITLNET_REQUIRE_NNS_PRIVILEGES();                  \
    SITLNET_REQUIRE(why_missing);                      \
    if (flies) SITLNET_REQUIRE(NodeMavlinkMissing());  \
  } while (0)

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The pid of the process named `comm` in robot "a"'s namespace (an observer, from outside), or 0.
pid_t AutopilotPid(const std::string& scenario, const std::string& comm) {
  std::istringstream pids(RunCommand({"ip", "netns", "pids", scenario + "-a"}).out);
  for (pid_t pid; pids >> pid;) {
    if (ReadAll("/proc/" + std::to_string(pid) + "/comm") == comm + "\n") return pid;
  }
  return 0;
}

// The shipped manifest with a restart policy added, as a user would copy it (a manifest file of
// its own, in the test's temporary folder).
std::string RestartingManifest(const std::string& image) {
  const std::string path = TempDir() + "/image_" + image + "_restarting.textproto";
  std::ofstream(path) << ReadAll(SourceDir() + "/robot_images/" + image + "/image.textproto")
                      << "restart: RESTART_ON_FAILURE\nmax_restarts: 1\n";
  return path;
}

// Robot "a"'s heights (ENU z, m) in trajectories.csv, one per 100 ms row.
std::vector<double> Heights(const std::string& out) {
  std::vector<double> z;
  std::istringstream lines(ReadAll(out + "/trajectories.csv"));
  for (std::string line; std::getline(lines, line);) {
    double t = 0, x = 0, y = 0, height = 0;
    int robot = -1;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf,%lf", &t, &robot, &x, &y, &height) == 5 &&
        robot == 0) {
      z.push_back(height);
    }
  }
  return z;
}

// The truth of a vehicle killed in the air and flown again: up (above half its altitude), then
// on the ground (fallen with its motors cut, or put back at its start by the reconnection), and
// at its altitude at the end.
void ExpectUpDownUp(const std::vector<double>& z, double start_z, double altitude_m) {
  ASSERT_FALSE(z.empty());
  const auto up = std::find_if(z.begin(), z.end(),
                               [&](double height) { return height - start_z > altitude_m / 2; });
  ASSERT_NE(up, z.end()) << "never flew";
  EXPECT_LT(*std::min_element(up, z.end()) - start_z, 0.5)
      << "not back on the ground between the flights";
  EXPECT_NEAR(z.back() - start_z, altitude_m, 0.3) << "not at its altitude again at the end";
}

// A failed test's run folder (robot logs, metrics, summary) and, as run.stderr, what the run
// printed outlive the test process's temporary folder: copied to /tmp/sitlnet-failed-<name>-<pid>,
// named in the output. SITLNET_TEST_KEEP_RUNS=1 keeps a passing run's too (to compare).
void KeepIfFailed(const std::string& out, const std::string& run_stderr) {
  if (!::testing::Test::HasFailure() && std::getenv("SITLNET_TEST_KEEP_RUNS") == nullptr) return;
  const std::string kept = "/tmp/sitlnet-failed-" + out.substr(out.rfind('/') + 1) + "-" +
                           std::to_string(getpid());
  RunCommand({"cp", "-a", out, kept});
  std::ofstream(kept + "/run.stderr") << run_stderr;
  std::printf("[ kept ] the failed run's folder: %s\n", kept.c_str());
}

int Occurrences(const std::string& text, const std::string& part) {
  int found = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
    ++found;
  }
  return found;
}

// The virtual time of the restarted PX4's first HIL_SENSOR, which its lockstep scheduler reports
// once per life ("setting initial absolute time to N us", lockstep_scheduler.cpp), as "; the
// restarted PX4's clock began at T s"; "" for ArduCopter, or a PX4 that did not get that far.
std::string RestartClockSaid(const std::string& log) {
  const std::string said = "setting initial absolute time to ";
  const size_t first = log.find(said);
  const size_t second = first == std::string::npos ? first : log.find(said, first + 1);
  if (second == std::string::npos) return "";
  char line[80];
  std::snprintf(line, sizeof line, "; the restarted PX4's clock began at %.1f s",
                std::strtod(log.c_str() + second + said.size(), nullptr) / 1e6);
  return line;
}

// The longest physics part of an iteration (metrics.csv's t_phy_ns, ms) after iteration `after`:
// in lockstep it holds the wait for the autopilot's answers, which the drop bounds (1 s here).
double LongestPhysicsMsAfter(const std::string& out, long after) {
  double longest_ms = 0;
  std::istringstream lines(ReadAll(out + "/metrics.csv"));
  for (std::string line; std::getline(lines, line);) {
    long iteration = 0;
    long long start_ns = 0, t_phy_ns = 0;
    if (std::sscanf(line.c_str(), "%ld,%lld,%lld", &iteration, &start_ns, &t_phy_ns) == 3 &&
        iteration > after) {
      longest_ms = std::max(longest_ms, t_phy_ns / 1e6);
    }
  }
  return longest_ms;
}

// The iteration of the first drop ("... of iteration N within ..."), or -1.
long DropIteration(const std::string& run_stderr) {
  const std::string said = " of iteration ";
  const size_t at = run_stderr.find(said, run_stderr.find("did not answer"));
  return at == std::string::npos ? -1 : std::strtol(run_stderr.c_str() + at + said.size(),
                                                      nullptr, 10);
}

long SummaryCount(const std::string& summary, const std::string& key) {
  const size_t at = summary.find("\"" + key + "\":");
  if (at == std::string::npos) return -1;
  return std::strtol(summary.c_str() + at + key.size() + 3, nullptr, 10);
}

// ------------------------------------------------------------------------------------------------
// Killed mid-flight. A ground station from tests/node_mavlink, in robot "a"'s namespace on the
// autopilot's own GCS link, arms it and takes it to 3 m; once the autopilot reports it there,
// the autopilot is killed (SIGKILL).

constexpr double kAltitudeM = 3;

struct Autopilot {
  std::string (*missing)();  // Why it cannot be run here, or "".
  const char* image;    // The shipped manifest.
  const char* process;  // Its process name (comm).
  const char* robot;    // The robot block, "IMAGE" for the image.
  double start_z;       // The robot's start height.
  // Starts the ground station once the autopilot (started for the `nth` time) listens.
  std::function<std::unique_ptr<Child>(const std::string& scenario, const std::string& out,
                                       int nth)>
      fly;
  const char* at_altitude;  // What the ground station prints once at kAltitudeM.
  const char* unanswered;   // The silent-robot line: "... did not answer <unanswered>".
  const char* expected;     // ... "<expected> within".
  const char* reconnect_key;  // summary.json's count that says the restart reconnected.
  long reconnect_count;
};

std::string WithImage(std::string robot, const std::string& image) {
  robot.replace(robot.find("IMAGE"), 5, image);
  return robot;
}

// Waits (2 min at most) until robot "a"'s log says `line` for the `nth` time (a restart appends
// to the log).
void WaitForLogLine(const std::string& out, const std::string& line, int nth) {
  const std::string log = out + "/robots/a.log";
  const auto said = [&] { return Occurrences(ReadAll(log), line) >= nth; };
  EXPECT_TRUE(WaitForFiles(out + "/robots", said, 120 * kNsPerS)) << ReadAll(log);
}

// node SCRIPT ARGS... in robot "a"'s namespace.
std::unique_ptr<Child> GroundStation(const std::string& scenario, const std::string& script,
                                     std::vector<std::string> args) {
  std::vector<std::string> argv = {"ip", "netns", "exec", scenario + "-a", "node",
                                   NodeMavlinkDir() + "/" + script};
  argv.insert(argv.end(), args.begin(), args.end());
  return std::make_unique<Child>(argv);
}

// PX4's GCS link is UDP on the robot's loopback (fly_px4.cjs): arm, take off, hold ("EVENT
// HOLD" once steady at the altitude), then a waypoint the test never lets it reach.
const Autopilot kPx4 = {
    Px4Missing, "px4", "px4",
    "robot { name: \"a\" position_m { z: 0.2 } image: \"IMAGE\" px4_sim_port: 4560 }\n", 0.2,
    [](const std::string& scenario, const std::string& out, int nth) {
      WaitForLogLine(out, "Startup script returned successfully", nth);
      return GroundStation(scenario, "fly_px4.cjs",
                           {std::to_string(kAltitudeM), "50", "0", "300"});
    },
    "EVENT HOLD", "its HIL_SENSOR of iteration ", "with HIL_ACTUATOR_CONTROLS", "connections", 2};

// ArduCopter's is TCP 5760 of the robot's loopback (guided_flight.cjs): GUIDED, arm, take off
// ("TAKEOFF_REACHED"), hold 600 s.
const Autopilot kArduCopter = {
    ArduPilotMissing, "arducopter", "arducopter",
    "robot { name: \"a\" position_m { z: 0.1 } image: \"IMAGE\" ardupilot_json_port: 9002 }\n",
    0.1,
    [](const std::string& scenario, const std::string& out, int nth) {
      WaitForLogLine(out, "SERIAL0 on TCP port 5760", nth);
      return GroundStation(scenario, "guided_flight.cjs",
                           {"127.0.0.1", "5760", std::to_string(kAltitudeM), "600", "0", "0"});
    },
    "TAKEOFF_REACHED", "its JSON reply of iteration ", "with a servo frame", "json_restarts", 1};

// Flies the autopilot to kAltitudeM and kills it; returns the wall instant of the kill.
std::chrono::steady_clock::time_point FlyAndKill(const Autopilot& autopilot,
                                                 const RunScenario& scenario,
                                                 const std::string& out,
                                                 std::unique_ptr<Child>* gcs) {
  *gcs = autopilot.fly(scenario.name, out, 1);
  if (!(*gcs)->WaitForOutput(false, autopilot.at_altitude, 300 * kNsPerS)) {
    // Once beside busy loops (load 20-35) PX4's estimator never passed its preflight checks
    // ("Attitude failure (roll)", "velocity estimate error") while the truth was a level vehicle
    // at rest and no sensor message was lost: what the autopilot said is the lead.
    const std::string log = ReadAll(out + "/robots/a.log");
    ADD_FAILURE() << "not at its altitude; the GCS saw:\n"
                  << (*gcs)->out().substr(0, 3000) << "\nrobot a's own log, first 6000 bytes:\n"
                  << log.substr(0, 6000);
  }
  const pid_t pid = AutopilotPid(scenario.name, autopilot.process);
  EXPECT_GT(pid, 0);
  if (pid > 0) kill(pid, SIGKILL);
  return std::chrono::steady_clock::now();
}

// A lockstep run of `autopilot` (its robot with `image`) in `slot`, with `extra` top-level
// fields, flown to kAltitudeM and killed there: what both kill tests start from.
struct KilledFlight {
  KilledFlight(const Autopilot& autopilot, const std::string& image, int slot,
               const std::string& extra)
      : scenario(WriteScenario(slot, WithImage(autopilot.robot, image), extra)),
        guard(scenario.name),
        out(TempDir() + "/" + scenario.name + "-out"),
        start(std::chrono::steady_clock::now()),
        run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"}),
        killed(FlyAndKill(autopilot, scenario, out, &gcs)) {}
  const RunScenario scenario;
  DownGuard guard;
  const std::string out;
  const std::chrono::steady_clock::time_point start;
  Child run;
  std::unique_ptr<Child> gcs;  // Declared before `killed`, which FlyAndKill sets it for.
  const std::chrono::steady_clock::time_point killed;
};

// Default on_silent_robot (SILENT_ROBOT_STOP): the run stops after silent_robot_timeout_ms (1 s)
// naming the robot and what it did not answer, exit 1, the outputs whole up to the stop, the
// vehicle at its altitude in the last rows.
void KilledMidFlightStopsTheRun(const Autopilot& autopilot, int slot) {
  SITLNET_REQUIRE_AUTOPILOT(autopilot.missing(), true);
  KilledFlight flight(autopilot, autopilot.image, slot,
                      "timing { duration_ms: 300000 pacing: PACING_LOCKSTEP }\n");
  const RunScenario& scenario = flight.scenario;
  const std::string& out = flight.out;
  Child& run = flight.run;
  const auto killed = flight.killed;
  EXPECT_EQ(run.Wait(60 * kNsPerS), 1) << run.err();
  const double stop_s = SecondsSince(killed);
  EXPECT_NE(run.err().find(std::string("robot 'a' did not answer ") + autopilot.unanswered),
            std::string::npos)
      << run.err();
  EXPECT_NE(run.err().find(std::string(autopilot.expected) + " within 1000 ms"), std::string::npos)
      << run.err();
  const std::vector<double> z = Heights(out);
  ASSERT_FALSE(z.empty());
  EXPECT_NEAR(z.back() - autopilot.start_z, kAltitudeM, 0.3) << "not at its altitude at the kill";
  std::printf("[ measured ] %s killed at %.1f m after %.1f s virtual; the run stopped %.2f s "
              "(wall) after the kill; %.1f s wall in all\n",
              autopilot.image, z.back() - autopilot.start_z, z.size() / 10.0, stop_s,
              SecondsSince(flight.start));
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// SILENT_ROBOT_DROP and a restart policy: the dead autopilot is dropped (motors cut: it falls),
// the supervisor starts it again, the new one reconnects (PX4: a new connection; ArduCopter: a
// smaller frame_count), which puts the robot back at its start; it boots, arms and climbs to its
// altitude again: the autopilot says so, and so does the truth. The run is then interrupted.
void KilledMidFlightIsDroppedAndRestartedFliesAgain(const Autopilot& autopilot, int slot) {
  SITLNET_REQUIRE_AUTOPILOT(autopilot.missing(), true);
  const std::string manifest = RestartingManifest(autopilot.image);
  // The duration is a cap (the test interrupts the run): from the drop until the restarted
  // autopilot answers again nothing holds the lockstep clock back, so it runs as fast as physics
  // steps (STF 0.015 at p50 here) while the autopilot boots on the wall clock. PX4 rebooting
  // beside two busy loops reconnected 246 s (virtual) after its kill; with a cap of 300 s, 1 run
  // of 13 ended before it flew again; 29 later runs reconnected at 37-606 s. An hour leaves room
  // and bounds what a failed run writes (metrics.csv, trajectories.csv) at about 54 s of wall.
  // The silent-robot timeout is the default, 1 s: it bounds every wait for an answer of both
  // lives, and a restarted PX4 dropped a second time flies with its motors cut (what CI saw:
  // armed, "Takeoff detected", no climb, the clock free at STF 0.07). Beside two busy loops (load
  // 20-35) the longest physics part of an iteration after the drop was 29-502 ms in 8 runs, 285
  // and 502 ms in two: the 300 ms this test used to set left no margin.
  KilledFlight flight(autopilot, manifest, slot,
                      "timing { duration_ms: 3600000 pacing: PACING_LOCKSTEP }\n"
                      "on_silent_robot: SILENT_ROBOT_DROP\n");
  const RunScenario& scenario = flight.scenario;
  const std::string& out = flight.out;
  Child& run = flight.run;
  std::unique_ptr<Child>& gcs = flight.gcs;
  const auto killed = flight.killed;
  gcs.reset();  // Its GCS port is the next one's.
  EXPECT_TRUE(run.WaitForOutput(true, "dropped from the run, motors cut", 30 * kNsPerS))
      << run.err();
  EXPECT_TRUE(run.WaitForOutput(true, "restarting robot \"a\" (1 of at most 1)", 30 * kNsPerS))
      << run.err();
  const double restarted_s = SecondsSince(killed);
  gcs = autopilot.fly(scenario.name, out, 2);
  if (!gcs->WaitForOutput(false, autopilot.at_altitude, 300 * kNsPerS)) {
    // Once in CI (2026-11-29) the restarted PX4 armed at 70.5 s and said "Takeoff detected" but
    // never climbed, and the run's 300 s ran out at STF 0.07: the clock ran free, so nothing
    // awaited PX4 (dropped a second time? The drop count below says). Its log holds both lives.
    const std::string log = ReadAll(out + "/robots/a.log");
    ADD_FAILURE() << "not at its altitude again; the GCS saw:\n"
                  << gcs->out().substr(0, 3000) << "\nrobot a's own log, last 6000 bytes:\n"
                  << log.substr(log.size() > 6000 ? log.size() - 6000 : 0);
  }
  const double flying_again_s = SecondsSince(killed);
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  EXPECT_NE(run.err().find(std::string("robot 'a' did not answer ") + autopilot.unanswered),
            std::string::npos)
      << run.err();
  // Dropped once, the killed one: a restarted autopilot dropped too (slow to answer once) would
  // fly with its motors cut for the rest of the run (a drop lasts until the next restart).
  EXPECT_EQ(Occurrences(run.err(), "dropped from the run, motors cut"), 1) << run.err();
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_EQ(SummaryCount(summary, autopilot.reconnect_key), autopilot.reconnect_count) << summary;
  const std::vector<double> z = Heights(out);
  ExpectUpDownUp(z, autopilot.start_z, kAltitudeM);
  std::printf("[ measured ] %s dropped and restarted %.2f s (wall) after the kill, at %.1f m "
              "again %.1f s after it; %.1f s virtual, %.1f s wall in all%s; after the drop the "
              "longest iteration's physics took %.0f ms (the drop's bound: 1000)\n",
              autopilot.image, restarted_s, z.back() - autopilot.start_z, flying_again_s,
              z.size() / 10.0, SecondsSince(flight.start),
              RestartClockSaid(ReadAll(out + "/robots/a.log")).c_str(),
              LongestPhysicsMsAfter(out, DropIteration(run.err())));
  ExpectNothingLeft(scenario.name);
  KeepIfFailed(out, run.err());
  RunCommand({"rm", "-rf", out, manifest});
}

TEST(AutopilotFaultsTest, Px4KilledMidFlightStopsTheLockstepRunNamingIt) {
  KilledMidFlightStopsTheRun(kPx4, 2);
}

TEST(AutopilotFaultsTest, Px4KilledMidFlightIsDroppedAndRestartedFliesAgain) {
  KilledMidFlightIsDroppedAndRestartedFliesAgain(kPx4, 3);
}

TEST(AutopilotFaultsTest, ArduCopterKilledMidFlightStopsTheLockstepRunNamingIt) {
  KilledMidFlightStopsTheRun(kArduCopter, 6);
}

TEST(AutopilotFaultsTest, ArduCopterKilledMidFlightIsDroppedAndRestartedFliesAgain) {
  KilledMidFlightIsDroppedAndRestartedFliesAgain(kArduCopter, 7);
}

// PX4 started as instance 1 connects to port 4561 (PX4's 4560 + instance), where nothing
// listens: in lockstep the run names it once its log and CPU have been still for 10 s (it waits
// at 15 % of a core: not booting), before the start bound (10 s + the manifest's 1.5 s), quoting
// what PX4 says it waits for.
TEST(AutopilotFaultsTest, APx4ThatNeverConnectsIsNamedWithinTheTimeout) {
  SITLNET_REQUIRE_AUTOPILOT(Px4Missing(), false);
  const RunScenario scenario = WriteScenario(
      4,
      "robot { name: \"a\" position_m { z: 0.2 } image: \"px4\" px4_sim_port: 4560 "
      "args: [\"-i\", \"1\"] }\n",
      "timing { duration_ms: 10000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  const CommandResult run = SitlnetRun(scenario, out, {});
  const double wall_s = SecondsSince(start);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("lockstep: robots a sent no MotorCommand (nor servo frame, nor PX4 "
                         "connection) and made no progress (log and CPU time still) for 10000 "
                         "ms; a's log ends \"INFO  "
                         "[simulator_mavlink] Waiting for simulator to accept connection on TCP "
                         "port 4561\""),
            std::string::npos)
      << run.err;
  EXPECT_LT(wall_s, 11.5 + 5) << "the bound, and the set-up and teardown around it";
  std::printf("[ measured ] named after %.1f s (wall)\n", wall_s);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// ------------------------------------------------------------------------------------------------
// Bad input: each case one line on stderr naming robot "a" and the cause, exit 2, nothing left.

struct BadInput {
  const char* what;
  std::string robot;                    // The robot block.
  std::vector<std::string> environment;  // Changed variables, NAME=VALUE.
  std::vector<std::string> expected;   // What the line says, in this order.
};

// A folder laid out as a PX4 build whose bin/px4 is `bytes` (executable or not).
std::string FakePx4Folder(const std::string& name, const std::string& bytes, bool executable) {
  const std::string dir = TempDir() + "/" + name;
  std::filesystem::create_directories(dir + "/bin");
  std::filesystem::create_directories(dir + "/etc");
  std::ofstream(dir + "/bin/px4", std::ios::binary) << bytes;
  std::filesystem::permissions(dir + "/bin/px4",
                               executable ? std::filesystem::perms::owner_all
                                          : std::filesystem::perms::owner_read |
                                                std::filesystem::perms::owner_write);
  return dir;
}

// The line of `err` that says each of `parts` in order, or "".
std::string LineSaying(const std::string& err, const std::vector<std::string>& parts) {
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);) {
    size_t at = 0;
    for (const std::string& part : parts) {
      at = line.find(part, at);
      if (at == std::string::npos) break;
    }
    if (at != std::string::npos) return line;
  }
  return "";
}

TEST(AutopilotFaultsTest, BadAutopilotsAreRefusedInOneLineNamingTheRobotAndTheCause) {
  SITLNET_REQUIRE_AUTOPILOT(Px4Missing(), false);
  SITLNET_REQUIRE_AUTOPILOT(ArduPilotMissing(), false);
  const std::string px4_robot = WithImage(kPx4.robot, "px4");
  const std::string wrong = TempDir() + "/no_px4_here";
  // Bytes that begin no known executable format, NULs among them (so the shell does not take
  // them for a script).
  std::string bytes;
  for (int i = 0; i < 4096; ++i) bytes += static_cast<char>((i * 37) % 251);
  const std::string garbage = FakePx4Folder("garbage_px4", bytes, true);
  const std::string not_executable =
      FakePx4Folder("plain_px4", "\x7f" "ELF not really\n", false);
  const std::vector<BadInput> cases = {
      {"a wrong SITLNET_PX4_DIR", px4_robot, {"SITLNET_PX4_DIR=" + wrong},
       {"sitlnet run: robot \"a\": image \"px4\" needs " + wrong + ", which does not exist"}},
      {"a file that is no program", px4_robot, {"SITLNET_PX4_DIR=" + garbage},
       {"sitlnet run: robot \"a\": its image exited at once with status 126; its log says "
        "\"px4: 1: exec: /tmp/px4/bin/px4: Exec format error\"; see "}},
      {"a program that may not be run", px4_robot, {"SITLNET_PX4_DIR=" + not_executable},
       {"sitlnet run: robot \"a\": its image exited at once with status 126; its log says "
        "\"px4: 1: exec: /tmp/px4/bin/px4: Permission denied\"; see "}},
      {"PX4 exits at boot (a flag it does not know)",
       "robot { name: \"a\" position_m { z: 0.2 } image: \"px4\" px4_sim_port: 4560 "
       "args: [\"--no-such-flag\"] }\n",
       {},
       // PX4 prints its usage before it exits: at once (within 300 ms of its start), or on a
       // busy host a moment later, before it spoke to physics.
       {"robot \"a\"", "status 255", "; its log says \"ERROR [px4] unrecognized flag\""}},
      {"ArduCopter exits at boot (a model it does not know)",
       "robot { name: \"a\" position_m { z: 0.1 } image: \"arducopter\" "
       "ardupilot_json_port: 9002 args: [\"--model\", \"no-such-model\"] }\n",
       {},
       {"robot \"a\"", "status 1", "; its log says \"Vehicle model (no-such-model) not found\""}},
      {"an image that exits a second after it started, before it spoke to physics",
       "robot { name: \"a\" position_m { z: 0.2 } image: \"shell\" px4_sim_port: 4560 "
       "args: \"sleep 1; echo cannot go on; exit 4\" }\n",
       {},
       {"lockstep: robot \"a\" exited (status 4) before it spoke to physics; its log says "
        "\"cannot go on\" (log: "}},
      {"a port the physics server uses already",
       "robot { name: \"a\" position_m { z: 0.2 } image: \"px4\" px4_sim_port: 9500 }\n",
       {},
       {"robot \"a\": px4_sim_port must be in [1, 65535] and differ from physics_port"}},
  };
  for (const BadInput& bad : cases) {
    SCOPED_TRACE(bad.what);
    const RunScenario scenario =
        WriteScenario(5, bad.robot, "timing { duration_ms: 10000 pacing: PACING_LOCKSTEP }\n");
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + "-out";
    std::vector<std::string> argv = {"env"};
    argv.insert(argv.end(), bad.environment.begin(), bad.environment.end());
    for (const std::string& arg :
         {SitlnetBinary(), std::string("run"), scenario.path, std::string("--out"), out,
          std::string("--no-progress")}) {
      argv.push_back(arg);
    }
    const auto start = std::chrono::steady_clock::now();
    const CommandResult run = RunCommand(argv, 60 * kNsPerS);
    const double wall_s = SecondsSince(start);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_LT(wall_s, 5) << "named when it happened, not at the readiness deadline (10 s)";
    const std::string line = LineSaying(run.err, bad.expected);
    EXPECT_NE(line, "") << run.err;
    // One line: the only one after the run's start line.
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'),
              1 + (run.err.find("starting medium") != std::string::npos))
        << run.err;
    std::printf("[ refused ] %s, in %.1f s: %s\n", bad.what, wall_s, line.c_str());
    ExpectNothingLeft(scenario.name);
    RunCommand({"rm", "-rf", out});
  }
  RunCommand({"rm", "-rf", garbage, not_executable});
}

}  // namespace
}  // namespace sitlnet::nns::testing

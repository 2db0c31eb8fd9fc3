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

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::Child;
using integration_test::IsCi;
using integration_test::ReadAll;
using integration_test::SitlnetBinary;
using integration_test::SourceDir;
using integration_test::TempDir;
using integration_test::WaitForFiles;

// Why the autopilot built in $`variable` (holding `program`) cannot be run here, or "". Flying
// it also needs node-mavlink.
std::string AutopilotMissing(const char* variable, const std::string& program, bool flies) {
  const char* dir = std::getenv(variable);
  if (dir == nullptr || *dir == '\0') {
    return std::string(variable) + " is not set: point it at the autopilot's build folder as "
           "docs/autopilots.md says";
  }
  if (!std::filesystem::exists(std::string(dir) + "/" + program)) {
    return std::string(variable) + "=" + dir + " holds no " + program + " (docs/autopilots.md)";
  }
  return flies ? NodeMavlinkMissing() : "";
}

// Skips (fails under CI=true) when the autopilot or node-mavlink is missing.
#define SITLNET_REQUIRE_AUTOPILOT(variable, program, flies)                             \
  do {                                                                                 \
    SITLNET_REQUIRE_NNS_PRIVILEGES();                                                  \
    if (const std::string missing = AutopilotMissing(variable, program, flies);        \
        !missing.empty()) {                                                            \
      if (IsCi()) FAIL() << missing;                                                   \
      GTEST_SKIP() << missing;                                                         \
    }                                                                                  \
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

long SummaryCount(const std::string& summary, const std::string& key) {
  const size_t at = summary.find("\"" + key + "\":");
  if (at == std::string::npos) return -1;
  return std::strtol(summary.c_str() + at + key.size() + 3, nullptr, 10);
}

// ------------------------------------------------------------------------------------------------
// PX4: fly_px4.cjs on PX4's own GCS link (the robot's loopback) arms it and takes it to 3 m; once
// PX4 has held that altitude for 3 s ("EVENT HOLD"), PX4 is killed.

constexpr double kPx4AltitudeM = 3;
constexpr double kStartZ = 0.2;  // The robot's start height.

const char* const kPx4Robot =
    "robot { name: \"a\" position_m { z: 0.2 } image: \"IMAGE\" px4_sim_port: 4560 }\n";

std::string WithImage(std::string robot, const std::string& image) {
  robot.replace(robot.find("IMAGE"), 5, image);
  return robot;
}

// node fly_px4.cjs in robot "a"'s namespace: arm, take off to kPx4AltitudeM, hold, ... .
std::unique_ptr<Child> FlyPx4(const std::string& scenario) {
  return std::make_unique<Child>(std::vector<std::string>{
      "ip", "netns", "exec", scenario + "-a", "node", NodeMavlinkDir() + "/fly_px4.cjs",
      std::to_string(kPx4AltitudeM), "50", "0", "300"});
}

// Starts the run, flies PX4 until it holds its altitude, kills PX4 (SIGKILL). Returns the wall
// instant of the kill.
std::chrono::steady_clock::time_point FlyAndKillPx4(const RunScenario& scenario, Child& run,
                                                    std::unique_ptr<Child>* fly) {
  EXPECT_TRUE(WaitForFiles(kNetnsDir, [&] { return NetnsExists(scenario.name + "-a"); },
                           60 * kNsPerS))
      << run.err();
  *fly = FlyPx4(scenario.name);
  EXPECT_TRUE((*fly)->WaitForOutput(false, "EVENT HOLD", 120 * kNsPerS))
      << (*fly)->out() << run.err();
  const pid_t px4 = AutopilotPid(scenario.name, "px4");
  EXPECT_GT(px4, 0);
  if (px4 > 0) kill(px4, SIGKILL);
  return std::chrono::steady_clock::now();
}

// Default on_silent_robot (SILENT_ROBOT_STOP): the run stops after silent_robot_timeout_ms (1 s)
// naming the robot and what it did not answer, exit 1, the outputs whole up to the stop.
TEST(AutopilotFaultsTest, Px4KilledMidFlightStopsTheLockstepRunNamingIt) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_PX4_DIR", "bin/px4", true);
  const RunScenario scenario = WriteScenario(
      2, WithImage(kPx4Robot, "px4"), "timing { duration_ms: 300000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  std::unique_ptr<Child> fly;
  const auto killed = FlyAndKillPx4(scenario, run, &fly);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 1) << run.err();
  const double stop_s = SecondsSince(killed);
  EXPECT_NE(run.err().find("robot 'a' did not answer its HIL_SENSOR of iteration "),
            std::string::npos)
      << run.err();
  EXPECT_NE(run.err().find("with HIL_ACTUATOR_CONTROLS within 1000 ms"), std::string::npos)
      << run.err();
  // Flying when it died: the last rows are at the altitude PX4 held.
  const std::vector<double> z = Heights(out);
  ASSERT_FALSE(z.empty());
  EXPECT_NEAR(z.back() - kStartZ, kPx4AltitudeM, 0.3) << "not at its altitude at the kill";
  std::printf("[ measured ] PX4 killed at %.1f m after %.1f s virtual; the run stopped %.2f s "
              "(wall) after the kill; %.1f s wall in all\n",
              z.back() - kStartZ, z.size() / 10.0, stop_s, SecondsSince(start));
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// SILENT_ROBOT_DROP and a restart policy: the dead PX4 is dropped (motors cut: it falls), the
// supervisor starts it again, the new PX4 connects (the robot back at its start), boots, arms and
// climbs to its altitude again: PX4 says so, and so does the truth. The run is then interrupted.
TEST(AutopilotFaultsTest, Px4KilledMidFlightIsDroppedAndRestartedFliesAgain) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_PX4_DIR", "bin/px4", true);
  const std::string manifest = RestartingManifest("px4");
  const RunScenario scenario =
      WriteScenario(3, WithImage(kPx4Robot, manifest),
                    "timing { duration_ms: 300000 pacing: PACING_LOCKSTEP }\n"
                    "silent_robot_timeout_ms: 300\non_silent_robot: SILENT_ROBOT_DROP\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  std::unique_ptr<Child> fly;
  const auto killed = FlyAndKillPx4(scenario, run, &fly);
  fly.reset();  // Its GCS port is the next one's.
  EXPECT_TRUE(run.WaitForOutput(true, "dropped from the run, motors cut", 30 * kNsPerS))
      << run.err();
  EXPECT_TRUE(run.WaitForOutput(true, "restarting robot \"a\" (1 of at most 1)", 30 * kNsPerS))
      << run.err();
  const double restarted_s = SecondsSince(killed);
  fly = FlyPx4(scenario.name);
  EXPECT_TRUE(fly->WaitForOutput(false, "EVENT HOLD", 120 * kNsPerS)) << fly->out() << run.err();
  const double flying_again_s = SecondsSince(killed);
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  EXPECT_NE(run.err().find("robot 'a' did not answer its HIL_SENSOR of iteration "),
            std::string::npos)
      << run.err();
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_EQ(SummaryCount(summary, "connections"), 2) << summary;
  // The truth: up at the kill, on the ground between the flights (fallen, then put back at its
  // start), up again at the end.
  const std::vector<double> z = Heights(out);
  ASSERT_FALSE(z.empty());
  ExpectUpDownUp(z, kStartZ, kPx4AltitudeM);
  std::printf("[ measured ] PX4 dropped and restarted %.2f s (wall) after the kill, at %.1f m "
              "again %.1f s after it; %.1f s virtual, %.1f s wall in all\n",
              restarted_s, z.back() - kStartZ, flying_again_s, z.size() / 10.0,
              SecondsSince(start));
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out, manifest});
}

// PX4 started as instance 1 connects to port 4561 (PX4's 4560 + instance), where nothing
// listens: in lockstep the run names it within the readiness bound (10 s + 250 ms per robot),
// quoting what PX4 says it waits for.
TEST(AutopilotFaultsTest, APx4ThatNeverConnectsIsNamedWithinTheTimeout) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_PX4_DIR", "bin/px4", false);
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
                         "connection) within 10250 ms of starting; a's log ends \"INFO  "
                         "[simulator_mavlink] Waiting for simulator to accept connection on TCP "
                         "port 4561\""),
            std::string::npos)
      << run.err;
  EXPECT_LT(wall_s, 10.25 + 5) << "the bound, and the set-up and teardown around it";
  std::printf("[ measured ] named after %.1f s (wall)\n", wall_s);
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// ------------------------------------------------------------------------------------------------
// ArduCopter: guided_flight.cjs on ArduCopter's SERIAL0 (TCP 5760 of the robot's loopback) sets
// GUIDED, arms, takes off to 3 m and holds; once ArduCopter reports the altitude reached
// ("TAKEOFF_REACHED"), it is killed.

constexpr double kCopterAltitudeM = 3;
constexpr double kCopterStartZ = 0.1;

const char* const kCopterRobot =
    "robot { name: \"a\" position_m { z: 0.1 } image: \"IMAGE\" ardupilot_json_port: 9002 }\n";

// Waits until robot "a"'s log says ArduCopter listens on SERIAL0 for the `nth` time (a restart
// appends to the log), then starts the ground station there.
std::unique_ptr<Child> FlyCopter(const std::string& scenario, const std::string& out, int nth) {
  const std::string log = out + "/robots/a.log";
  const auto listening = [&] {
    const std::string text = ReadAll(log);
    int found = 0;
    for (size_t at = text.find("SERIAL0 on TCP port 5760"); at != std::string::npos;
         at = text.find("SERIAL0 on TCP port 5760", at + 1)) {
      ++found;
    }
    return found >= nth;
  };
  EXPECT_TRUE(WaitForFiles(out + "/robots", listening, 120 * kNsPerS)) << ReadAll(log);
  return std::make_unique<Child>(std::vector<std::string>{
      "ip", "netns", "exec", scenario + "-a", "node", NodeMavlinkDir() + "/guided_flight.cjs",
      "127.0.0.1", "5760", std::to_string(kCopterAltitudeM), "600", "0", "0"});
}

std::chrono::steady_clock::time_point FlyAndKillCopter(const RunScenario& scenario,
                                                       const std::string& out,
                                                       std::unique_ptr<Child>* gcs) {
  *gcs = FlyCopter(scenario.name, out, 1);
  EXPECT_TRUE((*gcs)->WaitForOutput(false, "TAKEOFF_REACHED", 300 * kNsPerS)) << (*gcs)->out();
  const pid_t copter = AutopilotPid(scenario.name, "arducopter");
  EXPECT_GT(copter, 0);
  if (copter > 0) kill(copter, SIGKILL);
  return std::chrono::steady_clock::now();
}

TEST(AutopilotFaultsTest, ArduCopterKilledMidFlightStopsTheLockstepRunNamingIt) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_ARDUPILOT_DIR", "bin/arducopter", true);
  const RunScenario scenario =
      WriteScenario(6, WithImage(kCopterRobot, "arducopter"),
                    "timing { duration_ms: 300000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  std::unique_ptr<Child> gcs;
  const auto killed = FlyAndKillCopter(scenario, out, &gcs);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 1) << run.err();
  const double stop_s = SecondsSince(killed);
  EXPECT_NE(run.err().find("robot 'a' did not answer its JSON reply of iteration "),
            std::string::npos)
      << run.err();
  EXPECT_NE(run.err().find("with a servo frame within 1000 ms"), std::string::npos) << run.err();
  const std::vector<double> z = Heights(out);
  ASSERT_FALSE(z.empty());
  EXPECT_NEAR(z.back() - kCopterStartZ, kCopterAltitudeM, 0.3) << "not at its altitude at the kill";
  std::printf("[ measured ] ArduCopter killed at %.1f m after %.1f s virtual; the run stopped "
              "%.2f s (wall) after the kill; %.1f s wall in all\n",
              z.back() - kCopterStartZ, z.size() / 10.0, stop_s, SecondsSince(start));
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// As for PX4: dropped, restarted, back at its start (a new SITL's smaller frame_count), arms and
// reaches its altitude again.
TEST(AutopilotFaultsTest, ArduCopterKilledMidFlightIsDroppedAndRestartedFliesAgain) {
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_ARDUPILOT_DIR", "bin/arducopter", true);
  const std::string manifest = RestartingManifest("arducopter");
  const RunScenario scenario =
      WriteScenario(7, WithImage(kCopterRobot, manifest),
                    "timing { duration_ms: 300000 pacing: PACING_LOCKSTEP }\n"
                    "silent_robot_timeout_ms: 300\non_silent_robot: SILENT_ROBOT_DROP\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  std::unique_ptr<Child> gcs;
  const auto killed = FlyAndKillCopter(scenario, out, &gcs);
  EXPECT_TRUE(run.WaitForOutput(true, "dropped from the run, motors cut", 30 * kNsPerS))
      << run.err();
  EXPECT_TRUE(run.WaitForOutput(true, "restarting robot \"a\" (1 of at most 1)", 30 * kNsPerS))
      << run.err();
  const double restarted_s = SecondsSince(killed);
  gcs = FlyCopter(scenario.name, out, 2);
  EXPECT_TRUE(gcs->WaitForOutput(false, "TAKEOFF_REACHED", 300 * kNsPerS)) << gcs->out();
  const double flying_again_s = SecondsSince(killed);
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  EXPECT_NE(run.err().find("robot 'a' did not answer its JSON reply of iteration "),
            std::string::npos)
      << run.err();
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_EQ(SummaryCount(summary, "json_restarts"), 1) << summary;
  const std::vector<double> z = Heights(out);
  ASSERT_FALSE(z.empty());
  ExpectUpDownUp(z, kCopterStartZ, kCopterAltitudeM);
  std::printf("[ measured ] ArduCopter dropped and restarted %.2f s (wall) after the kill, at "
              "%.1f m again %.1f s after it; %.1f s virtual, %.1f s wall in all\n",
              restarted_s, z.back() - kCopterStartZ, flying_again_s, z.size() / 10.0,
              SecondsSince(start));
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out, manifest});
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
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_PX4_DIR", "bin/px4", false);
  SITLNET_REQUIRE_AUTOPILOT("SITLNET_ARDUPILOT_DIR", "bin/arducopter", false);
  const std::string px4_robot = WithImage(kPx4Robot, "px4");
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

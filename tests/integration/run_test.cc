// `sitlnet run` end to end with real namespaces, MuJoCo, the medium and the
// flocker image: lockstep reproducibility, robot failures, Ctrl-C, teardown.
#include <arpa/inet.h>
#include <linux/capability.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

// summary.json's derived metrics (docs/sweep-reference.md, "Metrics") against the files they
// summarise: the closest approach by brute force over trajectories.csv's rows (printed with
// 6 decimals, hence the 1 mm), and the delivery classes' frames against links.csv's sum.
void ExpectDerivedMetricsMatchTheirFiles(const std::string& run_dir) {
  const std::string summary = ReadAll(run_dir + "/summary.json");
  std::map<std::string, std::vector<std::array<double, 3>>> by_time;
  std::istringstream trajectories(ReadAll(run_dir + "/trajectories.csv"));
  std::string line;
  std::getline(trajectories, line);  // The header.
  while (std::getline(trajectories, line)) {
    std::istringstream row(line);
    std::string time, robot, x, y, z;
    std::getline(row, time, ',');
    std::getline(row, robot, ',');
    std::getline(row, x, ',');
    std::getline(row, y, ',');
    std::getline(row, z, ',');
    by_time[time].push_back({std::stod(x), std::stod(y), std::stod(z)});
  }
  double closest_m = INFINITY;
  for (const auto& [time, positions] : by_time) {
    for (size_t a = 0; a < positions.size(); ++a) {
      for (size_t b = a + 1; b < positions.size(); ++b) {
        closest_m = std::min(closest_m, std::hypot(positions[a][0] - positions[b][0],
                                                   positions[a][1] - positions[b][1],
                                                   positions[a][2] - positions[b][2]));
      }
    }
  }
  EXPECT_NEAR(SummaryNumber(summary, "\"separation\":", "\"min_m\":"), closest_m, 1e-3)
      << summary;
  uint64_t link_frames = 0;
  std::istringstream links(ReadAll(run_dir + "/links.csv"));
  std::getline(links, line);
  while (std::getline(links, line)) {
    std::istringstream row(line);
    std::string field;
    for (int column = 0; column < 4; ++column) std::getline(row, field, ',');
    link_frames += std::stoull(field);  // `frames`, the fourth column.
  }
  const double line_of_sight =
      SummaryNumber(summary, "\"line_of_sight\":", "\"frames\":");
  const double obstructed = SummaryNumber(summary, "\"obstructed\":", "\"frames\":");
  EXPECT_GT(link_frames, 0u);
  EXPECT_EQ(line_of_sight + obstructed, static_cast<double>(link_frames)) << summary;
}

TEST(RunTest, LockstepRunsAreByteIdenticalAndTheSeedMatters) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(0, kTwoFlockers, "timing { duration_ms: 5000 }\n");
  DownGuard guard(scenario.name);
  const std::string base = TempDir() + "/" + scenario.name + "-out";
  const CommandResult first =
      SitlnetRun(scenario, base + "1", {"--pacing", "lockstep", "--seed", "5"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const CommandResult second =
      SitlnetRun(scenario, base + "2", {"--pacing", "lockstep", "--seed", "5"});
  ASSERT_EQ(second.exit_code, 0) << second.err;
  const CommandResult other =
      SitlnetRun(scenario, base + "3", {"--pacing", "lockstep", "--seed", "6"});
  ASSERT_EQ(other.exit_code, 0) << other.err;
  // Without the loss recording (losses.csv.gz, links.csv) the rest is byte-identical.
  const CommandResult no_losses =
      SitlnetRun(scenario, base + "4", {"--pacing", "lockstep", "--seed", "5", "--no-losses"});
  ASSERT_EQ(no_losses.exit_code, 0) << no_losses.err;

  for (const char* file : {"scenario.textproto", "trajectories.csv", "metrics.csv", "medium.pcap",
                           "deliveries.csv", "connectivity.csv", "summary.json", "robots/a.log",
                           "trajectories.png", "connectivity.png", "stf.png", "losses.csv.gz",
                           "links.csv"}) {
    struct stat info {};
    EXPECT_EQ(stat((base + "1/" + file).c_str(), &info), 0) << file;
  }
  const std::string trajectories = ReadAll(base + "1/trajectories.csv");
  const std::string pcap = ReadAll(base + "1/medium.pcap");
  // 5 s at 10 Hz for 2 robots plus t=0 and the header; the robots flew.
  EXPECT_GE(std::count(trajectories.begin(), trajectories.end(), '\n'), 100);
  EXPECT_GT(pcap.size(), 24u + 20 * 100u);  // header + at least ~100 beacons
  EXPECT_EQ(trajectories, ReadAll(base + "2/trajectories.csv"));
  EXPECT_EQ(pcap, ReadAll(base + "2/medium.pcap"));
  EXPECT_EQ(ReadAll(base + "1/deliveries.csv"), ReadAll(base + "2/deliveries.csv"));
  EXPECT_EQ(ReadAll(base + "1/losses.csv.gz"), ReadAll(base + "2/losses.csv.gz"));
  EXPECT_EQ(ReadAll(base + "1/links.csv"), ReadAll(base + "2/links.csv"));
  for (const char* file : {"trajectories.csv", "medium.pcap", "deliveries.csv", "connectivity.csv"}) {
    EXPECT_EQ(ReadAll(base + "1/" + file), ReadAll(base + "4/" + file)) << file;
  }
  struct stat none {};
  EXPECT_NE(stat((base + "4/losses.csv.gz").c_str(), &none), 0);
  EXPECT_NE(stat((base + "4/links.csv").c_str(), &none), 0);
  // Another seed changes the medium's draws (backoff slots, intra-step offsets).
  EXPECT_NE(pcap, ReadAll(base + "3/medium.pcap"));
  ExpectDerivedMetricsMatchTheirFiles(base + "1");
  EXPECT_NE(ReadAll(base + "4/summary.json").find("\"delivery\":null"), std::string::npos);
  ExpectNothingLeft(scenario.name);
}

TEST(RunTest, ImageThatCannotStartIsNamedWithItsLogAndNothingIsLeft) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string manifest = TempDir() + "/run_test_missing_image.textproto";
  std::ofstream(manifest) << "name: \"missing\"\ncommand: \"/nonexistent/autopilot\"\n";
  const RunScenario scenario = WriteScenario(
      1, "robot { name: \"a\" image: \"" + manifest + "\" }\nrobot { name: \"b\" }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("robot \"a\""), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(out + "/robots/a.log"), std::string::npos) << result.err;
  EXPECT_NE(ReadAll(out + "/robots/a.log").find("/nonexistent/autopilot"), std::string::npos);
  ExpectNothingLeft(scenario.name);
}

// A robot inherits no file of the run: the pcap, the CSVs and the run's other descriptors are
// close-on-exec (an audit found medium.pcap open for writing in every robot).
TEST(RunTest, RobotsInheritNoFileOfTheRun) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(
      5,
      "robot { name: \"a\" image: \"shell\" args: \"ls -l /proc/self/fd; sleep 30\" }\n"
      "robot { name: \"b\" }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result =
      SitlnetRun(scenario, out, {"--pacing", "realtime", "--duration", "1"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string listing = ReadAll(out + "/robots/a.log");
  ASSERT_NE(listing.find("/proc/"), std::string::npos) << listing;  // ls ran and listed
  for (const char* file :
       {"medium.pcap", "deliveries.csv", "trajectories.csv", "metrics.csv", "losses.csv.gz"}) {
    EXPECT_EQ(listing.find(file), std::string::npos) << file << " is open in the robot:\n"
                                                     << listing;
  }
  ExpectNothingLeft(scenario.name);
}

TEST(RunTest, RobotFailureMidRunFollowsThePolicy) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string robots =
      "robot { name: \"a\" image: \"shell\" args: \"sleep 1; exit 3\" }\nrobot { name: \"b\" }\n";
  const RunScenario stop = WriteScenario(
      2, robots, "timing { duration_ms: 4000 }\non_robot_failure: ROBOT_FAILURE_STOP\n");
  {
    DownGuard guard(stop.name);
    const CommandResult result = SitlnetRun(stop, TempDir() + "/" + stop.name + "-out", {});
    EXPECT_EQ(result.exit_code, 1) << result.err;
    EXPECT_NE(result.err.find("robot \"a\" exited with status 3"), std::string::npos) << result.err;
    ExpectNothingLeft(stop.name);
  }
  const RunScenario go = WriteScenario(3, robots, "timing { duration_ms: 3000 }\n");
  DownGuard guard(go.name);
  const std::string out = TempDir() + "/" + go.name + "-out";
  const CommandResult result = SitlnetRun(go, out, {});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("robot \"a\" exited with status 3"), std::string::npos) << result.err;
  EXPECT_NE(ReadAll(out + "/summary.json").find("\"name\":\"a\",\"exit_status\":3"),
            std::string::npos);
  // The run went on to its end: 3 s of metrics rows (10 ms iterations) + header.
  const std::string metrics = ReadAll(out + "/metrics.csv");
  EXPECT_EQ(std::count(metrics.begin(), metrics.end(), '\n'), 301);
  ExpectNothingLeft(go.name);
}

TEST(RunTest, InterruptDuringStartUpLeavesNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(4, kTwoFlockers, "timing { duration_ms: 60000 }\n");
  DownGuard guard(scenario.name);
  Child run({SitlnetBinary(), "run", scenario.path, "--out",
             TempDir() + "/" + scenario.name + "-out", "--no-progress"});
  // Printed once the robots are up, before the medium, physics and images start.
  ASSERT_TRUE(run.WaitForOutput(true, "robots up", 30 * kNsPerS)) << run.err();
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  ExpectNothingLeft(scenario.name);
}

// Audit finding 6: a second `sitlnet run` (or `up`) of a scenario that is running tore the first
// one down. Now it is refused in one line naming the run, creates nothing, and the first run
// carries on.
TEST(RunTest, ASecondRunOfARunningScenarioIsRefusedAndTheFirstCarriesOn) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(9, kTwoFlockers, "timing { duration_ms: 60000 }\n");
  DownGuard guard(scenario.name);
  Child first({SitlnetBinary(), "run", scenario.path, "--out",
               TempDir() + "/" + scenario.name + "-first", "--no-progress"});
  ASSERT_TRUE(first.WaitForOutput(true, "robots up", 30 * kNsPerS)) << first.err();
  const std::string second_out = TempDir() + "/" + scenario.name + "-second";
  const CommandResult second = SitlnetRun(scenario, second_out, {});
  EXPECT_NE(second.exit_code, 0);
  EXPECT_NE(second.err.find("is running: sitlnet run (pid " + std::to_string(first.pid()) + ")"),
            std::string::npos)
      << second.err;
  EXPECT_EQ(std::count(second.err.begin(), second.err.end(), '\n'), 1) << second.err;
  struct stat info {};
  EXPECT_NE(stat(second_out.c_str(), &info), 0) << "the refused run made its folder";
  const CommandResult up = RunCommand({SitlnetBinary(), "up", scenario.path});
  EXPECT_NE(up.exit_code, 0);
  EXPECT_NE(up.err.find("is running"), std::string::npos) << up.err;
  // The first run is untouched: its namespaces are there and it is still running.
  EXPECT_TRUE(NetnsExists(scenario.name + "-a"));
  EXPECT_TRUE(NetnsExists(scenario.name + "-b"));
  EXPECT_EQ(kill(first.pid(), 0), 0);
  kill(first.pid(), SIGINT);
  EXPECT_EQ(first.Wait(60 * kNsPerS), 130) << first.err();
  ExpectNothingLeft(scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing

namespace sitlnet::nns::testing {
namespace {

TEST(DaemonTest, DownStopsTheScenariosMediumAndPhysicsDaemons) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(5, "robot { name: \"a\" }\nrobot { name: \"b\" }\n");
  DownGuard guard(scenario.name);
  ASSERT_EQ(RunCommand({SitlnetBinary(), "up", scenario.path}).exit_code, 0);
  Child medium({SitlnetBinary(), "medium", scenario.path});
  Child physics({SitlnetBinary(), "physics", scenario.path});
  ASSERT_TRUE(medium.WaitForOutput(true, "attached", 20 * kNsPerS)) << medium.err();
  ASSERT_TRUE(physics.WaitForOutput(true, "serving", 20 * kNsPerS)) << physics.err();
  EXPECT_EQ(RegisteredDaemons(scenario.name).size(), 2u);
  const CommandResult down = RunCommand({SitlnetBinary(), "down", scenario.name});
  EXPECT_EQ(down.exit_code, 0) << down.err;
  // Both stopped on SIGTERM (exit 0: they stop cleanly on it), not killed.
  EXPECT_EQ(medium.Wait(10 * kNsPerS), 0) << medium.err();
  EXPECT_EQ(physics.Wait(10 * kNsPerS), 0) << physics.err();
  ExpectNothingLeft(scenario.name);
  struct stat info {};
  EXPECT_NE(stat((std::string(kStateDir) + "/" + scenario.name).c_str(), &info), 0);
}

}  // namespace
}  // namespace sitlnet::nns::testing

namespace sitlnet::nns::testing {
namespace {

TEST(RunTest, RestartPolicyRestartsAFailingImageUpToItsLimit) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string manifest =
      WriteImageManifest("flaky",
                         "command: [\"/bin/sh\", \"-c\", \"echo started; sleep 0.5; exit 4\"]\n"
                         "restart: RESTART_ON_FAILURE\nmax_restarts: 2\n");
  const RunScenario scenario =
      WriteScenario(6, "robot { name: \"a\" image: \"" + manifest + "\" }\nrobot { name: \"b\" }\n",
                    "timing { duration_ms: 4000 }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("restarting robot \"a\" (1 of at most 2)"), std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("restarting robot \"a\" (2 of at most 2)"), std::string::npos);
  const std::string log = ReadAll(out + "/robots/a.log");
  size_t starts = 0;
  for (size_t at = log.find("started"); at != std::string::npos; at = log.find("started", at + 1)) {
    ++starts;
  }
  EXPECT_EQ(starts, 3u) << log;  // the first run and two restarts
  EXPECT_NE(ReadAll(out + "/summary.json").find("\"name\":\"a\",\"exit_status\":4"),
            std::string::npos);
  ExpectNothingLeft(scenario.name);
}

TEST(RunTest, ImageNotReadyInTimeIsAFailure) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string manifest = WriteImageManifest(
      "mute",
      "command: [\"/bin/sleep\", \"30\"]\nready_log_line: \"READY\"\nready_timeout_ms: 500\n");
  const RunScenario scenario =
      WriteScenario(7, "robot { name: \"a\" image: \"" + manifest + "\" }\nrobot { name: \"b\" }\n",
                    "timing { duration_ms: 5000 }\non_robot_failure: ROBOT_FAILURE_STOP\n");
  DownGuard guard(scenario.name);
  const CommandResult result = SitlnetRun(scenario, TempDir() + "/" + scenario.name + "-out", {});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("robot \"a\" not ready within 500 ms (no \"READY\" in its log)"),
            std::string::npos)
      << result.err;
  ExpectNothingLeft(scenario.name);
}

// Issue 17, finding 17: a run holds descriptors per robot; it raises its soft open-file limit as
// far as it needs (it used to fail with EMFILE near 250 robots under Debian's 1024). Here 24
// robots under a soft limit of 40. A hard limit below the need is raised by root
// (CAP_SYS_RESOURCE), else refused in one line that names the limit and the fix.
// Audit finding 18: a full disk under the run folder fails the run with one line naming the file
// and the error, and the scenario is torn down all the same. The disk: a 96 KiB tmpfs, mounted for
// this test and unmounted by name whatever happens.
TEST(RunTest, AFullDiskFailsTheRunNamingTheFile) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string disk = TempDir() + "/full-disk";
  RunCommand({"mkdir", "-p", disk});
  ASSERT_EQ(mount("tmpfs", disk.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=96k"), 0)
      << std::strerror(errno);
  struct Unmount {
    std::string path;
    ~Unmount() { umount2(path.c_str(), MNT_DETACH); }
  } unmount{disk};
  const RunScenario scenario = WriteScenario(14, kTwoFlockers, "timing { duration_ms: 20000 }\n");
  DownGuard guard(scenario.name);
  const CommandResult result =
      SitlnetRun(scenario, disk + "/out", {"--pacing", "lockstep", "--seed", "1"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("sitlnet run: write "), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(disk + "/out/"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("No space left on device"), std::string::npos) << result.err;
  ExpectNothingLeft(scenario.name);
}

// Audit finding 10: anyone may bind an address that is not there yet (IP_FREEBIND), so a local
// user could hold robot a's physics port before the run, and the run then failed at start ("robot
// \"a\": bind UDP ...: Address already in use", exit 2). The physics server's sockets are in the
// scenario's ctl namespace now: the port held in the host's namespace stops nothing.
TEST(RunTest, APhysicsPortHeldInTheHostsNamespaceStopsNoRun) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(15, kTwoFlockers, "timing { duration_ms: 1000 }\n");
  DownGuard guard(scenario.name);
  // Robot a's physics address: the root side (.1) of its ctl0 /30, default port 9500.
  const std::string address = "10.235." + std::to_string(getpid() % 250) + ".1";
  const int holder = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ASSERT_EQ(setsockopt(holder, IPPROTO_IP, IP_FREEBIND, &one, sizeof one), 0);
  sockaddr_in at{};
  at.sin_family = AF_INET;
  at.sin_port = htons(9500);
  ASSERT_EQ(inet_pton(AF_INET, address.c_str(), &at.sin_addr), 1);
  ASSERT_EQ(bind(holder, reinterpret_cast<const sockaddr*>(&at), sizeof at), 0)
      << std::strerror(errno);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {"--pacing", "lockstep"});
  close(holder);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  // Robot a's commands reached the server: every robot's physics counters show accepted ones.
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_EQ(summary.find("\"commands_accepted\":0,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"commands_accepted\":"), std::string::npos) << summary;
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// Audit finding 7: `sitlnet run` (root) writes only into a run folder it made or one that is the
// user's own and no one else can write; a link, someone else's folder or a world-writable one
// is refused in one line, before anything is written or set up, and the link's target stays
// untouched. (Before: any existing folder was used, a link followed.)
TEST(RunTest, ARunFolderThatIsALinkOrOthersCanWriteIsRefusedAndNothingIsWritten) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(15, kTwoFlockers, "timing { duration_ms: 500 }\n");
  DownGuard guard(scenario.name);
  const std::string base = TempDir() + "/" + scenario.name + "-folders";
  const std::string victim = base + "/victim";
  ASSERT_EQ(RunCommand({"mkdir", "-p", victim}).exit_code, 0);
  ASSERT_EQ(symlink(victim.c_str(), (base + "/link").c_str()), 0) << std::strerror(errno);
  ASSERT_EQ(mkdir((base + "/shared").c_str(), 0777), 0);
  ASSERT_EQ(chmod((base + "/shared").c_str(), 0777), 0);  // Past the umask.
  const auto refused = [&](const std::string& out, const std::string& why) {
    const CommandResult result = SitlnetRun(scenario, out, {"--pacing", "lockstep"});
    EXPECT_EQ(result.exit_code, 2) << result.err;
    const std::string named = out.back() == '/' ? out.substr(0, out.size() - 1) : out;
    EXPECT_NE(result.err.find("run folder \"" + named + "\" " + why), std::string::npos)
        << result.err;
    ExpectNothingLeft(scenario.name);
  };
  refused(base + "/link", "is a symbolic link");
  refused(base + "/link/", "is a symbolic link");
  EXPECT_EQ(RunCommand({"find", victim, "-mindepth", "1"}).out, "") << "written through the link";
  refused(base + "/shared", "can be written by others");
  EXPECT_EQ(RunCommand({"find", base + "/shared", "-mindepth", "1"}).out, "");
  // Someone else's folder (nobody's), when this process may give one away (CAP_CHOWN).
  ASSERT_EQ(mkdir((base + "/theirs").c_str(), 0755), 0);
  if (chown((base + "/theirs").c_str(), 65534, 65534) == 0) {
    refused(base + "/theirs", "belongs to user 65534");
  }
  RunCommand({"rm", "-rf", base});
}

TEST(RunTest, OpenFileLimitIsRaisedToWhatTheRobotsNeed) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  std::string robots;
  for (int i = 0; i < 24; ++i) {
    robots += "robot { name: \"r" + std::to_string(i) +
              "\" position_m { x: " + std::to_string(3 * i) + " y: 0 z: 0.2 } }\n";
  }
  const RunScenario scenario = WriteScenario(10, robots, "timing { duration_ms: 500 }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const auto run_with_limit = [&](const std::string& ulimit) {
    return RunCommand(
        {"/bin/sh", "-c", ulimit + " && exec \"$0\" run \"$1\" --out \"$2\" --no-progress",
         SitlnetBinary(), scenario.path, out},
        300 * kNsPerS);
  };
  const CommandResult soft = run_with_limit("ulimit -S -n 40");
  EXPECT_EQ(soft.exit_code, 0) << soft.err;
  const CommandResult hard = run_with_limit("ulimit -n 40");  // Soft and hard.
  if (HasCapability(CAP_SYS_RESOURCE)) {
    EXPECT_EQ(hard.exit_code, 0) << hard.err;
  } else {
    EXPECT_NE(hard.exit_code, 0);
    EXPECT_NE(hard.err.find("a run of 24 robots needs 256 open files, above the hard limit of 40"),
              std::string::npos)
        << hard.err;
  }
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// Times (and UDP lengths, when asked) of the frames of a run's medium.pcap that match a tshark
// display filter, first transmissions only (the capture has every MAC retry of a frame too). The
// capture's timestamps are virtual time.
// Echo requests per virtual second, from the second request on (iputils sends its second
// request early once, a transient of its first wait under libfaketime; docs/time.md).
double EchoRequestsPerVirtualSecond(const std::string& out, const std::string& to,
                                    size_t expected_requests, const std::string& log) {
  const std::vector<double> requests = CapturedTimes(out, "icmp.type == 8 && ip.dst == " + to);
  EXPECT_EQ(requests.size(), expected_requests) << log;
  if (requests.size() < 3) return 0;
  return (requests.size() - 2) / (requests.back() - requests[1]);
}

// iputils ping waits for each reply with a socket timeout of one interval (SO_RCVTIMEO), which
// the kernel ends on its timer wheel: a tick late for a short timeout, up to an eighth late for
// one of 64 ticks or more (docs/time.md). So `ping -i I` sends at most 1/I requests per second
// of its clock and, undilated on this host, 1/(1.04 I) for -i 0.1. Dilated, the same must hold
// per virtual second.
void ExpectPingRateFollowsItsClock(double requests_per_s, double interval_s) {
  EXPECT_GT(requests_per_s, 1 / (1.15 * interval_s)) << "echo requests per virtual second";
  EXPECT_LE(requests_per_s, 1.01 / interval_s) << "echo requests per virtual second";
}

// `iperf3 -u -b 2M -t 4` from `client`: its datagrams span 4 virtual seconds at 2 Mbit per
// virtual second on the medium, and iperf3's own receiver report (in its dilated seconds) agrees.
void ExpectIperf3TookFourVirtualSeconds(const std::string& out, const std::string& client,
                                        const std::string& client_log_path) {
  std::vector<int> lengths;
  const std::vector<double> datagrams =
      CapturedTimes(out, "udp.dstport == 5201 && ip.src == " + client, &lengths);
  const std::string client_log = ReadAll(client_log_path);
  ASSERT_GT(datagrams.size(), 100u) << client_log;
  const double span_s = datagrams.back() - datagrams.front();
  EXPECT_NEAR(span_s, 4.0, 4.0 * 0.02) << "iperf3 -t 4 in virtual seconds";
  int64_t payload_bytes = 0;
  for (int length : lengths) payload_bytes += length - 8;  // UDP header.
  const double medium_mbit_s = payload_bytes * 8 / span_s / 1e6;
  EXPECT_NEAR(medium_mbit_s, 2.0, 2.0 * 0.02) << "Mbit per virtual second on the medium";
  const size_t receiver = client_log.find("receiver");
  ASSERT_NE(receiver, std::string::npos) << client_log;
  const std::string line = client_log.substr(client_log.rfind('\n', receiver) + 1,
                                             receiver - client_log.rfind('\n', receiver));
  // Its own report's interval, "0.00-4.00 sec", in its dilated seconds.
  const size_t dash = line.find("0.00-");
  ASSERT_NE(dash, std::string::npos) << line;
  EXPECT_NEAR(std::stod(line.substr(dash + 5)), 4.0, 4.0 * 0.02) << line;
  const size_t mbits = line.find(" Mbits/sec");
  ASSERT_NE(mbits, std::string::npos) << line;
  const double reported = std::stod(line.substr(line.rfind(' ', mbits - 1) + 1));
  EXPECT_NEAR(reported, medium_mbit_s, medium_mbit_s * 0.02) << line;
}

// Issue 18: at realtime factor 0.25 the images' wall-clock programs live in virtual time through
// libfaketime (time: DILATED is the default when the factor is not 1), measured on the medium's
// capture, whose timestamps are virtual: `ping -i 0.1` sends about 10 requests per virtual
// second (ExpectPingRateFollowsItsClock), and `iperf3 -u -b 2M -t 4` lasts 4 virtual seconds at
// 2 Mbit/s of virtual time, as iperf3 itself reports. On the host's clock they would be 4 times
// as fast in virtual time.
TEST(RunTest, DilatedTimeAtAQuarterKeepsPingAndIperf3InVirtualTime) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string wlan =
      "10." + std::to_string(240 + 11) + "." + std::to_string(getpid() % 250) + ".";
  const RunScenario scenario =
      WriteScenario(11,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"shell\" "
                    "args: \"ping -n -i 0.1 -c 40 " +
                        wlan +
                        "2\" }\n"
                        "robot { name: \"b\" position_m { x: 5 y: 0 z: 0.2 } image: \"iperf\" "
                        "args: [\"-s\", \"-1\"] }\n"
                        "robot { name: \"c\" position_m { x: 0 y: 5 z: 0.2 } image: \"shell\" "
                        "args: \"sleep 0.5; iperf3 -c " +
                        wlan + "2 -u -b 2M -t 4\" }\n",
                    "timing { duration_ms: 6000 pacing: PACING_REALTIME realtime_factor: 0.25 }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ExpectPingRateFollowsItsClock(
      EchoRequestsPerVirtualSecond(out, wlan + "2", 40, ReadAll(out + "/robots/a.log")), 0.1);
  ExpectIperf3TookFourVirtualSeconds(out, wlan + "3", out + "/robots/c.log");
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
}

// Issue 18, faster than real time: at factor 2 the same programs, and babeld's hellos, keep
// their intervals in virtual time. iputils ping waits between requests with a socket timeout
// (SO_RCVTIMEO), which libfaketime leaves alone and sitlnet's companion library scales: without
// it ping sent one request per second of host time, two virtual seconds. The kernel ends such a
// wait on its timer wheel, which rounds a timeout of 64 ticks or more up by as much as an eighth
// (docs/time.md), so ping's rate may fall that far below 1/interval, never above. babeld draws each
// hello interval uniformly from [3/4, 5/4) of its configured interval (its `roughly`): one
// interval's standard deviation is 0.5 / sqrt(12) of the interval, so the mean of n intervals is
// compared within 4 / sqrt(n) of that, plus two 10 ms iterations for where the first and last hello
// were captured. About 35 hellos per robot make that about 11 %; on the host's clock the mean
// would be twice the interval.
// The run at f = 2 and its checks. Dilated clocks follow the wall clock, the medium the run's
// virtual time: they agree only while the run keeps real time. Returns true, checking nothing,
// when `may_run_again` and the run fell behind (lag above 20 ms, against about 1 ms when it keeps
// up): seen once in a CI rehearsal's container pass, ping's 8 intervals spanned 6.1 virtual s;
// or when ping's rate is off although the run kept up (seen once too, unexplained).
bool DilatedTimeAtTwiceRealTime(bool may_run_again) {
  const std::string wlan =
      "10." + std::to_string(240 + 11) + "." + std::to_string(getpid() % 250) + ".";
  // The slot of the test above: the two never run at once (one process, one test at a time).
  const RunScenario scenario =
      WriteScenario(11,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"babel\" "
                    "args: [\"-H\", \"0.2\"] }\n"
                    "robot { name: \"b\" position_m { x: 5 y: 0 z: 0.2 } image: \"iperf\" "
                    "args: [\"-s\", \"-1\"] }\n"
                    "robot { name: \"c\" position_m { x: 0 y: 5 z: 0.2 } image: \"shell\" "
                    "args: \"ping -n -i 1 -c 9 " +
                        wlan + "1 & sleep 0.5; iperf3 -c " + wlan +
                        "2 -u -b 2M -t 4; wait\" }\n"
                        "robot { name: \"d\" position_m { x: 5 y: 5 z: 0.2 } image: \"babel\" "
                        "args: [\"-H\", \"0.2\"] }\n",
                    "timing { duration_ms: 10000 pacing: PACING_REALTIME realtime_factor: 2 }\n",
                    "ipv6: IPV6_LINK_LOCAL");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  if (result.exit_code != 0) return false;
  const double lag_max_ms =
      SummaryNumber(ReadAll(out + "/summary.json"), "\"lag_ms\"", "\"max\":");
  if (may_run_again && !(lag_max_ms <= 20)) {
    std::printf("the run fell behind real time (lag max %.1f ms; %s): run once more\n", lag_max_ms,
                integration_test::HostLoad().c_str());
    ExpectNothingLeft(scenario.name);
    RunCommand({"rm", "-rf", out});
    return true;
  }
  std::printf("lag max %.2f ms\n", lag_max_ms);
  const std::string ping_log = ReadAll(out + "/robots/c.log");
  // Also seen once with the run on time (host pass, lag max 3.9 ms): 1.16 requests per virtual
  // second, cause not found (issue 43's closing note). Such a first run is shown, not judged.
  if (may_run_again) {
    const std::vector<double> requests =
        CapturedTimes(out, "icmp.type == 8 && ip.dst == " + wlan + "1");
    const double rate =
        requests.size() >= 3 ? (requests.size() - 2) / (requests.back() - requests[1]) : 0;
    if (!(rate > 1 / 1.15 && rate <= 1.01)) {
      std::string times;
      for (double t : requests) times += " " + std::to_string(t);
      std::printf("[ measured ] ping sent %.3f requests per virtual s (at%s); %s: run once more\n",
                  rate, times.c_str(), integration_test::HostLoad().c_str());
      ExpectNothingLeft(scenario.name);
      RunCommand({"rm", "-rf", out});
      return true;
    }
  }
  const double requests_per_s = EchoRequestsPerVirtualSecond(out, wlan + "1", 9, ping_log);
  ExpectPingRateFollowsItsClock(requests_per_s, 1.0);
  ExpectIperf3TookFourVirtualSeconds(out, wlan + "3", out + "/robots/c.log");
  // babeld's multicast hellos, per sender, from its second on (the first follows start-up).
  std::vector<std::string> sources;
  const std::vector<double> hellos = CapturedTimes(out,
                                                   "babel.message.type == 4 && "
                                                   "ipv6.dst == ff02::1:6",
                                                   nullptr, &sources);
  std::map<std::string, std::vector<double>> by_source;
  for (size_t i = 0; i < hellos.size(); ++i) by_source[sources[i]].push_back(hellos[i]);
  EXPECT_EQ(by_source.size(), 2u) << ReadAll(out + "/robots/a.log");
  for (const auto& [source, times] : by_source) {
    EXPECT_GT(times.size(), 20u) << source;
    if (times.size() < 3) continue;
    const double intervals = static_cast<double>(times.size() - 2);
    const double mean_interval_s = (times.back() - times[1]) / intervals;
    const double interval_sd_s = 0.2 * 0.5 / std::sqrt(12.0);
    const double tolerance_s = 4 * interval_sd_s / std::sqrt(intervals) + 2 * 0.010 / intervals;
    EXPECT_NEAR(mean_interval_s, 0.2, tolerance_s)
        << source << ": babeld -H 0.2, virtual s, over " << intervals << " intervals";
  }
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out});
  return false;
}

TEST(RunTest, DilatedTimeAtTwiceRealTimeKeepsPingIperf3AndBabeldInVirtualTime) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  // Once more at most: the second run is judged whatever the host did.
  if (DilatedTimeAtTwiceRealTime(/*may_run_again=*/true)) DilatedTimeAtTwiceRealTime(false);
}
// Issue 18: ROS 2's /clock in a robot, received by a Cyclone DDS subscriber with the same IDL and
// QoS as ROS 2's time source (ros2_clock_echo), in both pacings; its times are the run's virtual
// time (multiples of the 10 ms iteration, 20 ms apart at 50 Hz when nothing is skipped), and no
// DDS packet goes over the simulated radio.
std::vector<TimeNs> ClockTimes(const std::string& echo_output) {
  std::vector<TimeNs> times;
  std::istringstream lines(echo_output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("clock ", 0) != 0) continue;
    const size_t dot = line.find('.');
    times.push_back(std::stoll(line.substr(6, dot - 6)) * kNsPerS +
                    std::stoll(line.substr(dot + 1)));
  }
  return times;
}

void ExpectVirtualClock(const std::vector<TimeNs>& times, TimeNs duration_ns, bool every_tick) {
  ASSERT_EQ(times.size(), 20u);
  for (size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(times[i] % (10 * kNsPerMs), 0) << times[i];  // An iteration's end.
    EXPECT_LE(times[i], duration_ns);
    if (i == 0) continue;
    EXPECT_GT(times[i], times[i - 1]);
    if (every_tick) {
      EXPECT_EQ(times[i] - times[i - 1], 20 * kNsPerMs) << i;
    }
  }
}

TEST(RunTest, Ros2ClockReachesARobotOnItsLoopbackInBothPacings) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string echo =
      SitlnetBinary().substr(0, SitlnetBinary().rfind('/')) + "/ros2_clock_echo";
  // Realtime: the subscriber is the robot's image.
  const std::string manifest =
      WriteImageManifest("clock_echo", "command: [\"" + echo + "\", \"--count\", \"20\"]\n"
                                       "files: \"" + echo + "\"\n");
  const RunScenario realtime =
      WriteScenario(12,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"" + manifest +
                        "\" }\n"
                        "robot { name: \"b\" position_m { x: 5 y: 0 z: 0.2 } }\n",
                    "timing { duration_ms: 3000 ros2_clock_hz: 50 }\n");
  {
    DownGuard guard(realtime.name);
    const std::string out = TempDir() + "/" + realtime.name + "-out";
    const CommandResult result = SitlnetRun(realtime, out, {});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const std::string log = ReadAll(out + "/robots/a.log");
    ExpectVirtualClock(ClockTimes(log), 3 * kNsPerS, /*every_tick=*/true);
    const CommandResult rtps = RunCommand(
        {"tshark", "-r", out + "/medium.pcap", "-Y", "rtps", "-T", "fields", "-e", "frame.number"},
        60 * kNsPerS);
    EXPECT_EQ(rtps.exit_code, 0) << rtps.err;
    EXPECT_EQ(rtps.out, "") << "DDS on the radio";
    ExpectNothingLeft(realtime.name);
    RunCommand({"rm", "-rf", out});
  }
  // Lockstep: robots without images need not speak, so the run starts at once; the subscriber
  // joins robot b from outside (`sitlnet exec`) while the run goes on, then the run is stopped.
  const RunScenario lockstep =
      WriteScenario(13,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } }\n"
                    "robot { name: \"b\" position_m { x: 5 y: 0 z: 0.2 } }\n",
                    "timing { duration_ms: 600000 pacing: PACING_LOCKSTEP ros2_clock_hz: 50 }\n");
  DownGuard guard(lockstep.name);
  const std::string out = TempDir() + "/" + lockstep.name + "-out";
  RunCommand({"mkdir", "-p", out + "/robots"});
  Child run({SitlnetBinary(), "run", lockstep.path, "--out", out, "--no-progress"});
  const std::string publisher_log = out + "/robots/b.ros2_clock.log";
  ASSERT_TRUE(WaitForFiles(
      out + "/robots",
      [&] { return ReadAll(publisher_log).find("/clock at") != std::string::npos; }, 60 * kNsPerS))
      << run.err();
  const CommandResult received = RunCommand(
      {SitlnetBinary(), "exec", "--scenario", lockstep.name, "b", "--", echo, "--count", "20"},
      60 * kNsPerS);
  EXPECT_EQ(received.exit_code, 0) << received.err;
  ExpectVirtualClock(ClockTimes(received.out), 600 * kNsPerS, /*every_tick=*/false);
  kill(run.pid(), SIGINT);  // Ctrl-C: the run stops in order.
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  ExpectNothingLeft(lockstep.name);
  RunCommand({"rm", "-rf", out});
}

// Realtime pacing: sitlnet's own threads ask for SCHED_FIFO kDefaultRealtimePriority (a busy
// host otherwise delays the loop by milliseconds, docs/performance.md); the robot's software must
// not inherit it. The image reports its own policy and its parent's (the `sitlnet run` process)
// with chrt. It runs without the sandbox, whose PID namespace would hide the parent, and says so
// in a warning.
TEST(RunTest, RealtimeRunIsFifoButItsImagesAreNot) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string manifest = WriteImageManifest(
      "unconfined", "command: [\"/bin/sh\", \"-c\", \"${ARGS}\"]\nsandbox: NONE\n");
  const RunScenario scenario = WriteScenario(
      8,
      "robot { name: \"a\" image: \"" + manifest +
          "\" "
          "args: \"echo self; chrt -p $$; echo parent; chrt -p $PPID; exec sleep 60\" }\n"
          "robot { name: \"b\" }\n",
      "timing { duration_ms: 2000 pacing: PACING_REALTIME }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult result = SitlnetRun(scenario, out, {});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("warning: robot \"a\": image \"unconfined\" runs without a sandbox"),
            std::string::npos)
      << result.err;
  const std::string log = ReadAll(out + "/robots/a.log");
  const size_t parent = log.find("parent");
  ASSERT_NE(parent, std::string::npos) << log;
  const std::string self_part = log.substr(0, parent);
  const std::string parent_part = log.substr(parent);
  EXPECT_NE(self_part.find("policy: SCHED_OTHER"), std::string::npos) << log;
  if (HasCapability(CAP_SYS_NICE)) {
    EXPECT_NE(parent_part.find("policy: SCHED_FIFO"), std::string::npos) << log;
    EXPECT_NE(parent_part.find("priority: " + std::to_string(kDefaultRealtimePriority)),
              std::string::npos)
        << log;
    // Started under `chrt -f 5`: that choice stands and the image inherits it, as from any program.
    const std::string chrt_out = out + "-chrt";
    const CommandResult chrt = RunCommand({"chrt", "-f", "5", SitlnetBinary(), "run", scenario.path,
                                           "--out", chrt_out, "--no-progress"},
                                          300 * kNsPerS);
    ASSERT_EQ(chrt.exit_code, 0) << chrt.err;
    const std::string chrt_log = ReadAll(chrt_out + "/robots/a.log");
    EXPECT_EQ(chrt_log.find("SCHED_OTHER"), std::string::npos) << chrt_log;
    EXPECT_NE(chrt_log.find("priority: 5"), std::string::npos) << chrt_log;
    EXPECT_EQ(chrt_log.find("priority: " + std::to_string(kDefaultRealtimePriority)),
              std::string::npos)
        << chrt_log;
  } else {
    // Without CAP_SYS_NICE (e.g. the min-caps pass): one warning, then normal scheduling.
    EXPECT_NE(
        result.err.find("SCHED_FIFO priority " + std::to_string(kDefaultRealtimePriority) +
                        " refused (needs CAP_SYS_NICE or RLIMIT_RTPRIO)"),
        std::string::npos)
        << result.err;
    EXPECT_NE(parent_part.find("policy: SCHED_OTHER"), std::string::npos) << log;
  }
  ExpectNothingLeft(scenario.name);
}

// The start bound follows the fleet (issue 46, item 5): a boot that keeps logging is waited for
// past the 10 s stall window, up to the bound its manifest's boot_cost_ms makes; a robot that is
// still (no log, no CPU) is named after 10 s although the scenario's bound is a minute; and the
// scenario's bound, when set, is the bound.
TEST(RunTest, TheStartBoundWaitsForABootThatProgressesAndNamesOneThatIsStill) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  // Logs a line a second for 12 s, then flies: beyond the stall window and the 10.25 s bound a
  // robot of the default boot cost would have.
  const std::string slow = WriteImageManifest(
      "slowlogger",
      "command: [\"/bin/sh\", \"-c\", \"for i in 1 2 3 4 5 6 7 8 9 10 11 12; do echo booting "
      "$i; sleep 1; done; exec \\\"$@\\\"\", \"sh\", \"${SITLNET_BIN}/flocker\", \"--airframe\", "
      "\"${AIRFRAME}\"]\nsandbox: NONE\nboot_cost_ms: 5000\n");
  const std::string still =
      WriteImageManifest("stillboot", "command: [\"/bin/sleep\", \"60\"]\nsandbox: NONE\n");
  struct Case {
    std::string image, timing_extra, expect;
    double min_s, max_s;
  };
  const std::vector<Case> cases = {
      {slow, "", "", 12, 60},
      {still, "start_timeout_ms: 60000", "and made no progress (log and CPU time still) for 10000 ms",
       10, 20},
      {slow, "start_timeout_ms: 3000", "within the start bound, 3000 ms (timing.start_timeout_ms); "
       "a's log ends \"booting ", 3, 8},
  };
  for (const Case& c : cases) {
    const RunScenario scenario = WriteScenario(
        9, "robot { name: \"a\" position_m { z: 0.2 } image: \"" + c.image + "\" }\n",
        "timing { duration_ms: 1000 pacing: PACING_LOCKSTEP " + c.timing_extra + " }\n");
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + "-start";
    const auto start = std::chrono::steady_clock::now();
    const CommandResult result = SitlnetRun(scenario, out, {});
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (c.expect.empty()) {
      EXPECT_EQ(result.exit_code, 0) << result.err;
    } else {
      EXPECT_EQ(result.exit_code, 2) << result.err;
      EXPECT_NE(result.err.find("lockstep: robots a sent no MotorCommand (nor servo frame, nor "
                                "PX4 connection) " + c.expect),
                std::string::npos)
          << result.err;
    }
    EXPECT_GE(wall_s, c.min_s) << result.err;
    EXPECT_LT(wall_s, c.max_s) << result.err;
    std::printf("[ measured ] %s %s: %.1f s (wall)\n", c.image.c_str(), c.timing_extra.c_str(),
                wall_s);
    ExpectNothingLeft(scenario.name);
    RunCommand({"rm", "-rf", out});
  }
}

// First "t=" of a flocker log: the virtual time of the first state it received (s), or -1.
double FirstStateTimeS(const std::string& log) {
  const size_t at = log.find("t=");
  return at == std::string::npos ? -1 : std::atof(log.c_str() + at + 2);
}

TEST(RunTest, WaitForRobotsStartsTheRealtimeClockOnceTheImagesHaveSpoken) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  // A flocker that boots for 2 s of wall time before it speaks to physics.
  const std::string manifest = WriteImageManifest(
      "slowboot",
      "command: [\"/bin/sh\", \"-c\", \"sleep 2; exec \\\"$@\\\"\", \"sh\", "
      "\"${SITLNET_BIN}/flocker\", \"--airframe\", \"${AIRFRAME}\"]\nsandbox: NONE\n");
  const std::string robots = "robot { name: \"a\" position_m { z: 0.2 } image: \"" + manifest +
                             "\" }\nrobot { name: \"b\" position_m { y: 6 z: 0.2 } }\n";
  for (const bool wait : {true, false}) {
    const RunScenario scenario = WriteScenario(
        9, robots,
        std::string("timing { duration_ms: 4000 pacing: PACING_REALTIME wait_for_robots: ") +
            (wait ? "true" : "false") + " }\n");
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + (wait ? "-wait" : "-nowait");
    const CommandResult result = SitlnetRun(scenario, out, {});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    // With the wait the first state reaches it within the first iterations of virtual time;
    // without, more than a second of the run has gone by while it booted.
    const std::string log = ReadAll(out + "/robots/a.log");
    const double first_s = FirstStateTimeS(log);
    ASSERT_GE(first_s, 0) << log;
    if (wait) {
      EXPECT_LT(first_s, 0.5) << log;
    } else {
      EXPECT_GE(first_s, 1.0) << log;
    }
    ExpectNothingLeft(scenario.name);
  }
  // An image that never speaks to physics stops such a run before its clock starts, named; one
  // that exits meanwhile stops it at once, with its status.
  for (const std::string& command : {std::string("[\"/bin/sleep\", \"60\"]"),
                                     std::string("[\"/bin/sh\", \"-c\", \"sleep 0.5; exit 3\"]")}) {
    const bool exits = command.find("exit 3") != std::string::npos;
    const std::string silent =
        WriteImageManifest("silent", "command: " + command + "\nsandbox: NONE\n");
    const RunScenario scenario = WriteScenario(
        9, "robot { name: \"a\" image: \"" + silent + "\" }\n",
        "timing { duration_ms: 3000 pacing: PACING_REALTIME wait_for_robots: true }\n");
    DownGuard guard(scenario.name);
    const CommandResult result = SitlnetRun(scenario, TempDir() + "/" + scenario.name + "-q", {});
    EXPECT_NE(result.exit_code, 0) << result.err;  // 2, as lockstep's silent robots
    EXPECT_NE(result.err.find(exits ? "wait_for_robots: robot \"a\" exited (status 3) before it "
                                      "spoke to physics"
                                    : "wait_for_robots: robots a sent no MotorCommand"),
              std::string::npos)
        << result.err;
    ExpectNothingLeft(scenario.name);
  }
}

}  // namespace
}  // namespace sitlnet::nns::testing

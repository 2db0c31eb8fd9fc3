// `sitlnet sweep` end to end (docs/sweep.md): a lockstep sweep of 2 rates x 2 seeds, 2 at once,
// of a 1 s scenario with 2 flockers. Points in different job slots (names, ctl subnets, ports)
// give the same bytes, capture included; a rerun runs nothing finished; a failing point is recorded; Ctrl-C leaves nothing.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <regex>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

constexpr char kPoints[4][32] = {"radio.rate_mbps=6,seed=1", "radio.rate_mbps=6,seed=2",
                                 "radio.rate_mbps=54,seed=1", "radio.rate_mbps=54,seed=2"};

// Two flockers, lockstep, on subnets of this process (10.190/10.191, no other test's); the sweep
// moves the ctl subnet up one /24 per job slot, so each process takes two: 2k and 2k + 1.
std::string WriteSweepScenario(const std::string& dir, int duration_ms) {
  const std::string third = std::to_string(getpid() % 125 * 2);
  const std::string path = dir + "/sweep.textproto";
  std::ofstream(path) << "name: \"sweep\"\n"
                         "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"flocker\" "
                         "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
                         "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"flocker\" "
                         "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
                         "addresses { wlan_subnet: \"10.190."
                      << third << ".0/24\" ctl_subnet: \"10.191." << third
                      << ".0/24\" }\n"
                         "timing { duration_ms: "
                      << duration_ms << " pacing: PACING_LOCKSTEP }\n";
  return path;
}

CommandResult Sweep(const std::string& scenario, const std::string& out, const std::string& jobs) {
  return RunCommand({SitlnetBinary(), "sweep", scenario, "--seeds", "1-2", "--set",
                     "radio.rate_mbps=6,54", "--jobs", jobs, "--out", out},
                    120 * kNsPerS);
}

// The scenario name a point ran under (its job slot's).
std::string PointScenarioName(const std::string& folder) {
  std::smatch match;
  const std::string text = ReadAll(folder + "/point.textproto");
  return std::regex_search(text, match, std::regex("name: \"(sw[0-9]+_[0-9]+)\"")) ? match[1].str()
                                                                                  : "";
}

int64_t ModifiedNs(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) < 0) return -1;
  return info.st_mtim.tv_sec * kNsPerS + info.st_mtim.tv_nsec;
}

TEST(SweepTest, RunsClashFreeReproduciblyResumesAndRecordsAFailure) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string dir = TempDir();
  const std::string scenario = WriteSweepScenario(dir, 1000);
  const std::string out = dir + "/sweep-a";
  // One point made to fail: a run folder that others can write is refused by `sitlnet run`.
  const std::string failing = out + "/" + kPoints[3];
  ASSERT_EQ(RunCommand({"mkdir", "-p", failing}).exit_code, 0);
  ASSERT_EQ(chmod(failing.c_str(), 0777), 0);

  const CommandResult first = Sweep(scenario, out, "2");
  EXPECT_EQ(first.exit_code, 1) << first.err;
  const std::string points = ReadAll(out + "/points.csv");
  EXPECT_EQ(std::count(points.begin(), points.end(), '\n'), 5) << points;  // Header + 4 points.
  for (int p = 0; p < 3; ++p) {
    EXPECT_NE(points.find(std::string("\"") + kPoints[p] + "\"," + (p < 2 ? "6," : "54,") +
                          std::to_string(p % 2 + 1) + ",ok,"),
              std::string::npos)
        << points;
  }
  EXPECT_NE(points.find("\"radio.rate_mbps=54,seed=2\",54,2,failed,\"exit 2: sitlnet run: run folder"),
            std::string::npos)
      << points;
  EXPECT_NE(first.err.find("can be written by others"), std::string::npos) << first.err;
  // Two at once: both job slots were used, under two names.
  EXPECT_NE(PointScenarioName(out + "/" + kPoints[0]), PointScenarioName(out + "/" + kPoints[1]));

  // The same sweep one at a time (every point in slot 0): the same bytes, point by point.
  const std::string reference = dir + "/sweep-b";
  const CommandResult serial = Sweep(scenario, reference, "1");
  ASSERT_EQ(serial.exit_code, 0) << serial.err;
  for (int p = 0; p < 3; ++p) {
    for (const char* file : {"trajectories.csv", "deliveries.csv", "medium.pcap"}) {
      const std::string ours = ReadAll(out + "/" + kPoints[p] + "/" + file);
      EXPECT_FALSE(ours.empty()) << kPoints[p] << " " << file;
      EXPECT_EQ(ours, ReadAll(reference + "/" + kPoints[p] + "/" + file)) << kPoints[p] << " " << file;
    }
  }
  // ... and the seed matters: the medium's draws differ between seeds 1 and 2.
  EXPECT_NE(ReadAll(reference + "/" + kPoints[0] + "/deliveries.csv"),
            ReadAll(reference + "/" + kPoints[1] + "/deliveries.csv"));

  // Resume: the failed point alone runs again (its folder now fixed); the finished ones are kept.
  ASSERT_EQ(chmod(failing.c_str(), 0755), 0);
  std::vector<int64_t> before;
  for (int p = 0; p < 3; ++p) before.push_back(ModifiedNs(out + "/" + kPoints[p] + "/summary.json"));
  const CommandResult resumed = Sweep(scenario, out, "2");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("4 points, 3 finished before, 1 to run"), std::string::npos)
      << resumed.err;
  for (int p = 0; p < 3; ++p) {
    EXPECT_EQ(ModifiedNs(out + "/" + kPoints[p] + "/summary.json"), before[p]) << kPoints[p];
  }
  EXPECT_EQ(ReadAll(failing + "/trajectories.csv"),
            ReadAll(reference + "/" + kPoints[3] + "/trajectories.csv"));
  const std::string summary = ReadAll(out + "/summary.csv");
  EXPECT_NE(summary.find("54,metrics.stf.mean,2,"), std::string::npos) << summary;
  for (int p = 0; p < 4; ++p) ExpectNothingLeft(PointScenarioName(out + "/" + kPoints[p]));
}

TEST(SweepTest, CtrlCStopsTheRunsAndLeavesNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const std::string dir = TempDir();
  const std::string scenario = WriteSweepScenario(dir, 600000);  // Ten minutes: never reached.
  const std::string out = dir + "/sweep-stopped";
  integration_test::Child sweep({SitlnetBinary(), "sweep", scenario, "--seeds", "1-2", "--set",
                                 "radio.rate_mbps=6,54", "--jobs", "2", "--out", out});
  // Both first points flying: each run's trajectories.csv has rows.
  const auto flying = [&] {
    for (int p = 0; p < 2; ++p) {
      if (ReadAll(out + "/" + kPoints[p] + "/robots/a.log").find("t=") == std::string::npos) {
        return false;
      }
    }
    return true;
  };
  ASSERT_TRUE(WaitForFiles(out + "/" + kPoints[1] + "/robots", flying, 60 * kNsPerS));
  kill(sweep.pid(), SIGINT);
  EXPECT_EQ(sweep.Wait(60 * kNsPerS), 130) << sweep.err();
  const std::string points = ReadAll(out + "/points.csv");
  EXPECT_NE(points.find(",1,not_run,"), std::string::npos) << points;
  EXPECT_EQ(points.find(",ok,"), std::string::npos) << points;
  for (int p = 0; p < 2; ++p) ExpectNothingLeft(PointScenarioName(out + "/" + kPoints[p]));
}

}  // namespace
}  // namespace sitlnet::nns::testing

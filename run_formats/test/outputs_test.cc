#include "run_formats/run_formats.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace sitlnet::run_formats {
namespace {

bool IsPng(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char magic[8] = {};
  file.read(magic, 8);
  return file && std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

TEST(OutputsTest, PoseRowsAreOneCsvLineEach) {
  PoseRow row;
  row.time_ns = 1'500'000'000;
  row.robot = 3;
  row.x_m = 1.25;
  const std::string line = FormatPoseRow(row);
  EXPECT_EQ(line.rfind("1.500,3,1.2500,", 0), 0u) << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), ','),
            std::count(kTrajectoryHeader, kTrajectoryHeader + sizeof kTrajectoryHeader, ','));
}

// The run folder's name is the user's (--out) and may hold a quote: it must not become gnuplot
// commands. Named `<base>/q'; system 'touch INJECTED'; cd 'q`, the folder used to turn the
// script's `cd '<folder>'` into a shell command run in <base>/q (issue 17, finding 7).
TEST(OutputsTest, GnuplotDrawsThreePngsAndTheFolderNameIsNoCommand) {
  const std::string base = ::testing::TempDir() + "/outputs_test_plots";
  std::filesystem::remove_all(base);
  mkdir(base.c_str(), 0755);
  mkdir((base + "/q").c_str(), 0755);
  const std::string dir = base + "/q'; system 'touch INJECTED'; cd 'q";
  mkdir(dir.c_str(), 0755);
  const Scenario scenario = LoadScenarioText(
      "name: \"p\"\nrobot { name: \"a\" }\nrobot { name: \"b\" }\n"
      "obstacle { center_m { x: 5 y: 0 } size_m { x: 2 y: 4 z: 10 } yaw_deg: 30 }\n",
      "p.textproto");
  {
    LineFile trajectories(dir + "/trajectories.csv", kTrajectoryHeader);
    for (int k = 0; k < 10; ++k) {
      for (int robot = 0; robot < 2; ++robot) {
        PoseRow row;
        row.time_ns = k * kNsPerS;
        row.robot = robot;
        row.x_m = k;
        row.y_m = robot * 3;
        trajectories.Append(FormatPoseRow(row));
      }
    }
    LineFile metrics(dir + "/metrics.csv",
                     "iteration,start_ns,t_phy_ns,t_net_ns,t_total_ns,t_overhead_ns,stf,lag_ns");
    metrics.Append("0,0,1,1,2,1,0.2,0");
    metrics.Append("1,10000000,1,1,2,1,0.3,0");
  }
  WriteConnectivityCsv(dir + "/connectivity.csv",
                       ConnectivityTracker(2, kNsPerS, kNsPerS).Finish(3 * kNsPerS), 2);
  std::vector<std::string> warnings;
  const auto pngs = DrawPlots(dir, scenario, "test", &warnings);
  ASSERT_TRUE(warnings.empty()) << warnings[0];
  ASSERT_EQ(pngs.size(), 3u);
  for (const std::string& png : pngs) EXPECT_TRUE(IsPng(png)) << png;
  EXPECT_NE(access((base + "/q/INJECTED").c_str(), F_OK), 0) << "the folder name ran a command";
  std::filesystem::remove_all(base);
}

}  // namespace
}  // namespace sitlnet::run_formats

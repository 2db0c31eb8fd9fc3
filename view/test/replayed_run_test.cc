// Reading a run folder: every file, and one line naming what is missing or malformed.
#include "view/replayed_run.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "view/test/run_folder_fixture.h"

namespace sitlnet::view {
namespace {

using testing::WriteFile;
using testing::WriteRunFolder;

constexpr char kLosses[] =
    "1000,0,1,DATA,5,0,1,decoded,-1,-60.0,30.0,,\n"
    "2000,0,-1,DATA,6,0,1,collision,1,-70.0,2.0,,\n"
    "3000,1,-1,DATA,7,,1,queue_full,-1,,,,\n";

std::string LoadError(const std::string& dir) {
  try {
    LoadReplayedRun(dir);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(RunRecordTest, ReadsEveryFile) {
  const ReplayedRun record = LoadReplayedRun(WriteRunFolder("run_record_ok", kLosses));
  EXPECT_EQ(record.scenario.name, "vt");
  ASSERT_EQ(record.poses.size(), 6u);
  EXPECT_EQ(record.poses[5].time_ns, 200 * kNsPerMs);
  EXPECT_EQ(record.poses[5].robot, 1);
  EXPECT_DOUBLE_EQ(record.poses[5].x_m, 9.5);
  EXPECT_DOUBLE_EQ(record.poses[5].y_m, -0.5);
  ASSERT_EQ(record.links.size(), 2u);
  EXPECT_DOUBLE_EQ(record.links[0].delivery_ratio, 0.75);
  EXPECT_LT(record.links[1].delivery_ratio, 0);  // Only drops: the file leaves it empty.
  EXPECT_EQ(record.links[1].main_cause, "queue_full");
  EXPECT_DOUBLE_EQ(record.links[0].rate_mbps, 54);
  EXPECT_EQ(record.links[0].mcs, -1);  // 11a: the file leaves it empty
  ASSERT_EQ(record.losses.size(), 3u);
  EXPECT_EQ(record.losses[1].cells[7], "collision");
  EXPECT_EQ(record.losses_by_link.at({0, 1}), (std::vector<size_t>{0, 1}));
  EXPECT_EQ(record.losses_by_link.at({1, 1}), (std::vector<size_t>{2}));
}

TEST(RunRecordTest, AMissingFileIsNamedWithWhy) {
  const std::string dir = WriteRunFolder("run_record_no_losses", kLosses);
  std::filesystem::remove(dir + "/losses.csv.gz");
  EXPECT_EQ(LoadError(dir), "run folder \"" + dir +
                                "\" is incomplete: no losses.csv.gz (a run of an older sitlnet, "
                                "or one with --no-losses or --remote network)");
  std::filesystem::remove(dir + "/summary.json");
  EXPECT_NE(LoadError(dir).find("no summary.json (the run did not finish)"), std::string::npos);
  EXPECT_NE(LoadError(dir + "/nothing").find("No such file or directory"), std::string::npos);
}

// A run folder written before links.csv named rates (8 columns) still loads.
TEST(RunRecordTest, ALinksCsvWithoutRatesStillLoads) {
  const std::string dir = WriteRunFolder("run_record_old_links", kLosses);
  WriteFile(dir + "/links.csv",
            "second,from,to,frames,delivered,delivery_ratio,main_cause,main_cause_frames\n"
            "0,0,1,4,3,0.75,collision,1\n");
  const ReplayedRun record = LoadReplayedRun(dir);
  ASSERT_EQ(record.links.size(), 1u);
  EXPECT_DOUBLE_EQ(record.links[0].delivery_ratio, 0.75);
  EXPECT_DOUBLE_EQ(record.links[0].rate_mbps, 0);
  EXPECT_EQ(record.links[0].mcs, -1);
}

TEST(RunRecordTest, AnotherVersionsHeaderAndABadRowAreNamed) {
  const std::string dir = WriteRunFolder("run_record_bad", kLosses);
  WriteFile(dir + "/links.csv", "second,from,to,frames\n");
  EXPECT_NE(LoadError(dir).find(dir + "/links.csv:1: header is not"), std::string::npos);
  WriteRunFolder("run_record_bad", "1000,0,1,DATA,5,0,1,decoded,-1,-60.0,30.0,,\nx,0\n");
  EXPECT_EQ(LoadError(dir), dir + "/losses.csv.gz:3: 2 fields, not 13");
  WriteRunFolder("run_record_bad", "1000,0,1,DATA,5,0,zz,decoded,-1,-60.0,30.0,,\n");
  EXPECT_EQ(LoadError(dir), dir + "/losses.csv.gz:2: station \"zz\" is not a number");
}

}  // namespace
}  // namespace sitlnet::view

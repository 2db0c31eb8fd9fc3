// The page's JSON documents: what a link's frame list selects, the run's robots and obstacles.
#include "view/replay_json.h"

#include <gtest/gtest.h>

#include "view/test/run_folder_fixture.h"

namespace sitlnet::view {
namespace {

// Frames by 0 reaching station 1 around the second [1 s, 2 s), out of time order as the medium
// writes them (by end of transmission), one of another link and one at each edge.
constexpr char kLosses[] =
    "1500000000,0,1,DATA,2,0,1,collision,2,-70.0,2.0,,\n"
    "999999999,0,1,DATA,1,0,1,decoded,-1,-60.0,30.0,,\n"
    "1000000000,0,1,DATA,3,1,1,decoded,-1,-60.0,30.0,,\n"
    "1200000000,0,1,DATA,4,0,1,below_threshold,-1,-90.0,-1.0,95.0,9.0\n"
    "1100000000,0,-1,DATA,5,0,0,own_transmission,-1,,,,\n"
    "2000000000,0,1,DATA,6,0,1,decoded,-1,-60.0,30.0,,\n";

TEST(ReplayJsonTest, FramesOfALinkInASecondInTimeOrder) {
  const ReplayedRun record = LoadReplayedRun(testing::WriteRunFolder("replay_json_frames", kLosses));
  EXPECT_EQ(FramesJson(record, 0, 1, 2 * kNsPerS, kNsPerS),
            "{\"from\":0,\"station\":1,\"start_ns\":1000000000,\"end_ns\":2000000000,\"total\":3,"
            "\"rows\":["
            "[\"1000000000\",\"0\",\"1\",\"DATA\",\"3\",\"1\",\"1\",\"decoded\",\"-1\",\"-60.0\","
            "\"30.0\",\"\",\"\"],"
            "[\"1200000000\",\"0\",\"1\",\"DATA\",\"4\",\"0\",\"1\",\"below_threshold\",\"-1\","
            "\"-90.0\",\"-1.0\",\"95.0\",\"9.0\"],"
            "[\"1500000000\",\"0\",\"1\",\"DATA\",\"2\",\"0\",\"1\",\"collision\",\"2\",\"-70.0\","
            "\"2.0\",\"\",\"\"]]}");
  EXPECT_EQ(FramesJson(record, 1, 0, 2 * kNsPerS, kNsPerS),
            "{\"from\":1,\"station\":0,\"start_ns\":1000000000,\"end_ns\":2000000000,\"total\":0,"
            "\"rows\":[]}");
}

TEST(ReplayJsonTest, RunTrajectoriesAndLinks) {
  const ReplayedRun record = LoadReplayedRun(testing::WriteRunFolder("replay_json_run", ""));
  const std::string run = RunJson(record);
  EXPECT_NE(run.find("\"robots\":[{\"index\":0,\"name\":\"a\",\"autopilot\":null},"
                     "{\"index\":1,\"name\":\"b\",\"autopilot\":null}]"),
            std::string::npos)
      << run;
  EXPECT_NE(run.find("{\"name\":\"wall\",\"center_m\":[5,5,2],\"size_m\":[2,4,4],\"yaw_deg\":90}"),
            std::string::npos) << run;
  EXPECT_NE(run.find("\"end_s\":0.2,"), std::string::npos) << run;
  EXPECT_NE(run.find("\"loss_columns\":[\"time_ns\",\"from\","), std::string::npos) << run;
  // Speed from the velocity (3, 4, 0): 5 m/s.
  EXPECT_EQ(TrajectoriesJson(record),
            "{\"robots\":[[[0,0,0,0.2,5],[0.1,0.5,0,1,5],[0.2,1,0.1,2,5]],"
            "[[0,10,0,0.2,5],[0.1,10,-0.25,1,5],[0.2,9.5,-0.5,2,5]]]}");
  EXPECT_EQ(LinksJson(record),
            "{\"links\":[[0,0,1,4,3,0.75,\"collision\",1],[0,1,-1,0,0,null,\"queue_full\",2]]}");
}

// The components where they change (the third row repeats the second), and per second the
// mean and largest STF and the largest lag of its iterations.
TEST(ReplayJsonTest, TimelineOfComponentsAndTimingPerSecond) {
  const ReplayedRun record = LoadReplayedRun(testing::WriteRunFolder("replay_json_timeline", ""));
  EXPECT_EQ(TimelineJson(record),
            "{\"connectivity\":[[0.1,2,[0,1]],[0.2,1,[0,0]]],"
            "\"timing\":[[0,2,0.375,0.5,2],[1,1,1.5,1.5,0]]}");
}

}  // namespace
}  // namespace sitlnet::view

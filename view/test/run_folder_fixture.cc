#include "view/test/run_folder_fixture.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>

#include "run_formats/run_formats.h"

namespace sitlnet::view::testing {

void WriteFile(const std::string& path, const std::string& text, bool gzip) {
  if (!gzip) {
    std::ofstream(path, std::ios::binary) << text;
    return;
  }
  gzFile file = gzopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr) << path;
  EXPECT_EQ(gzwrite(file, text.data(), text.size()), static_cast<int>(text.size()));
  gzclose(file);
}

std::string WriteRunFolder(const std::string& name, const std::string& losses) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  WriteFile(dir + "/scenario.textproto",
            "name: \"vt\"\n"
            "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } }\n"
            "robot { name: \"b\" position_m { x: 10 y: 0 z: 0.2 } }\n"
            "obstacle { name: \"wall\" center_m { x: 5 y: 5 z: 2 } size_m { x: 2 y: 4 z: 4 } "
            "yaw_deg: 90 }\n");
  std::string trajectories = std::string(run_formats::kTrajectoryHeader) + "\n";
  for (const char* row :
       {"0.000,0,0.0000,0.0000,0.2000", "0.000,1,10.0000,0.0000,0.2000",
        "0.100,0,0.5000,0.0000,1.0000", "0.100,1,10.0000,-0.2500,1.0000",
        "0.200,0,1.0000,0.1000,2.0000", "0.200,1,9.5000,-0.5000,2.0000"}) {
    trajectories += std::string(row) +
                    ",1.000000,0.000000,0.000000,0.000000,3.0000,4.0000,0.0000,"
                    "47.39774200,8.54559400,488.2000\n";
  }
  WriteFile(dir + "/trajectories.csv", trajectories);
  WriteFile(dir + "/links.csv",
            std::string(run_formats::kLinkHeader) +
                "\n0,0,1,4,3,0.75,collision,1,54,\n0,1,-1,0,0,,queue_full,2,0,\n");
  WriteFile(dir + "/losses.csv.gz", std::string(run_formats::kLossHeader) + "\n" + losses, true);
  // Apart at 0.1 s, together at 0.2 s and 0.3 s (the last is no change).
  WriteFile(dir + "/connectivity.csv",
            "time_s,components,robot_0,robot_1\n0.100000,2,0,1\n0.200000,1,0,0\n"
            "0.300000,1,0,0\n");
  // Two iterations in second 0, one in second 1.
  WriteFile(dir + "/metrics.csv",
            "iteration,start_ns,t_phy_ns,t_net_ns,t_total_ns,t_overhead_ns,stf,lag_ns\n"
            "0,0,1,1,1,0,0.500000,0\n1,500000000,1,1,1,0,0.250000,2000000\n"
            "2,1000000000,1,1,1,0,1.500000,0\n");
  WriteFile(dir + "/summary.json", "{\"scenario\":\"vt\"}\n");
  return dir;
}

}  // namespace sitlnet::view::testing

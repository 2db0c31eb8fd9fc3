// The cause line quoted from a robot's log when it could not start (run_formats/log_cause.cc). The
// logs are what the real autopilots printed in tests/integration/autopilot_faults_test.cc.
#include "run_formats/run_formats.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace sitlnet::run_formats {
namespace {

TEST(LogCause, TheFirstComplaintOfAProgramThatExitedIsItsCause) {
  // PX4 v1.14.4 given an unknown flag: its complaint, then its usage text.
  const std::string px4 =
      "ERROR [px4] unrecognized flag\nUsage for Server/daemon process: \n\n    px4 [-h|-d]\n"
      "Usage for client: \n\n    px4-MODULE [--instance <instance>] command using symlink.\n"
      "        e.g.: px4-commander status\n";
  EXPECT_EQ(FirstErrorLine(px4), "ERROR [px4] unrecognized flag");
  // The shell that could not run a file that is no program.
  EXPECT_EQ(FirstErrorLine("px4: 1: exec: /tmp/px4/bin/px4: Exec format error\n"),
            "px4: 1: exec: /tmp/px4/bin/px4: Exec format error");
  // Nothing reads like an error: the last line.
  EXPECT_EQ(FirstErrorLine("Vehicle model (nosuch) is unknown\n\n"),
            "Vehicle model (nosuch) is unknown");
  EXPECT_EQ(FirstErrorLine(""), "");
}

TEST(LogCause, TheLastLineOfAProgramThatRunsSaysWhatItWaitsFor) {
  EXPECT_EQ(LastLine("ERROR [param] Parameter IMU_GYRO_FFT_EN not found.\nINFO  [simulator_mavlink] "
                     "Waiting for simulator to accept connection on TCP port 4561\n  \n"),
            "INFO  [simulator_mavlink] Waiting for simulator to accept connection on TCP port 4561");
}

TEST(LogCause, LinesAreCleanedAndCut) {
  EXPECT_EQ(LastLine("\x1b[31mred\x1b[0m  \r\n"), "[31mred[0m");
  const std::string cut = LastLine(std::string(500, 'x'));
  EXPECT_EQ(cut.size(), 200u);
  EXPECT_EQ(cut.substr(197), "...");
  EXPECT_EQ(LogSays("x"), "; its log says \"x\"");
  EXPECT_EQ(LogSays(""), "");
}

TEST(LogCause, ALongLogKeepsItsEndWithoutACutFirstLine) {
  const std::string path = ::testing::TempDir() + "/log_cause_test.log";
  {
    std::ofstream file(path);
    file << std::string(100, 'a') << "\nsecond\nthird\n";
  }
  EXPECT_EQ(ReadLogTail(path, 10), "third\n");
  EXPECT_EQ(ReadLogTail(path), std::string(100, 'a') + "\nsecond\nthird\n");
  EXPECT_EQ(ReadLogTail(path + ".none"), "");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace sitlnet::run_formats

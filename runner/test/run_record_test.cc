// summary.json's "outputs": every file the run wrote, with its hash (Sha256HexOfFile, itself
// tested against sha256sum in common/test/sha256_test.cc) and size from stat(2); summary.json
// and an earlier run's files not written again left out, whatever their times say.
#include "runner/run_record.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <unistd.h>

#include <fstream>
#include <string>

namespace sitlnet::runner {
namespace {

TEST(RunRecordTest, HashesEveryFileTheRunWrote) {
  const std::string dir = ::testing::TempDir() + "/run_record_" + std::to_string(getpid());
  ASSERT_EQ(mkdir(dir.c_str(), 0755), 0);
  ASSERT_EQ(mkdir((dir + "/robots").c_str(), 0755), 0);
  // Two files of an earlier run in the same folder: one this run leaves alone, stamped an hour
  // in the future (a shared volume's clock ahead of this host's: its time says nothing), and one
  // this run writes again.
  std::ofstream(dir + "/gcs.tlog") << "an earlier run's";
  const timeval an_hour_on[2] = {{time(nullptr) + 3600, 0}, {time(nullptr) + 3600, 0}};
  ASSERT_EQ(utimes((dir + "/gcs.tlog").c_str(), an_hour_on), 0);
  std::ofstream(dir + "/trajectories.csv") << "an earlier run's";
  const RunFolderFiles before = ListRunFolderFiles(dir);
  ASSERT_EQ(before.size(), 2u);
  ASSERT_EQ(symlink("/nonexistent", (dir + "/dangling").c_str()), 0);  // skipped, no failure
  std::ofstream(dir + "/trajectories.csv") << "time_s,robot\n0.000,0\n";
  std::ofstream(dir + "/robots/a.log") << "flocker up\n";
  std::ofstream(dir + "/medium.pcap", std::ios::binary) << std::string("\xd4\xc3\xb2\xa1\0\0", 6);
  std::ofstream(dir + "/summary.json") << "{}";

  const std::vector<OutputHash> outputs = HashOutputs(dir, before);
  // Sorted by path; summary.json and the earlier run's gcs.tlog left out.
  ASSERT_EQ(outputs.size(), 3u);
  const char* paths[] = {"medium.pcap", "robots/a.log", "trajectories.csv"};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(outputs[i].path, paths[i]);
    EXPECT_EQ(outputs[i].sha256, Sha256HexOfFile(dir + "/" + paths[i])) << paths[i];
    struct stat info {};
    ASSERT_EQ(stat((dir + "/" + paths[i]).c_str(), &info), 0);
    EXPECT_EQ(outputs[i].bytes, static_cast<uint64_t>(info.st_size)) << paths[i];
  }
}

}  // namespace
}  // namespace sitlnet::runner

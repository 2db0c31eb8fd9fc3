// summary.json's "outputs": every file the run wrote, with its hash (Sha256HexOfFile, itself
// tested against sha256sum in common/test/sha256_test.cc) and size from stat(2); summary.json
// and an earlier run's files left out.
#include "runner/run_record.h"

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
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
  // An earlier run's file in the same folder, last written an hour ago.
  std::ofstream(dir + "/gcs.tlog") << "an earlier run's";
  const timeval an_hour_ago[2] = {{time(nullptr) - 3600, 0}, {time(nullptr) - 3600, 0}};
  ASSERT_EQ(utimes((dir + "/gcs.tlog").c_str(), an_hour_ago), 0);
  const TimeNs since_ns = CoarseRealtimeNowNs();
  std::ofstream(dir + "/trajectories.csv") << "time_s,robot\n0.000,0\n";
  std::ofstream(dir + "/robots/a.log") << "flocker up\n";
  std::ofstream(dir + "/medium.pcap", std::ios::binary) << std::string("\xd4\xc3\xb2\xa1\0\0", 6);
  std::ofstream(dir + "/summary.json") << "{}";

  google::protobuf::Struct outputs;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(OutputsJson(dir, since_ns), &outputs)
                  .ok());
  ASSERT_EQ(outputs.fields_size(), 3) << "summary.json and the earlier run's gcs.tlog left out";
  for (const char* path : {"trajectories.csv", "robots/a.log", "medium.pcap"}) {
    ASSERT_EQ(outputs.fields().count(path), 1u) << path;
    const auto& entry = outputs.fields().at(path).struct_value().fields();
    EXPECT_EQ(entry.at("sha256").string_value(), Sha256HexOfFile(dir + "/" + path)) << path;
    struct stat info {};
    ASSERT_EQ(stat((dir + "/" + path).c_str(), &info), 0);
    EXPECT_EQ(entry.at("bytes").number_value(), static_cast<double>(info.st_size)) << path;
  }
}

}  // namespace
}  // namespace sitlnet::runner

// gcs.tlog's layout, by the format's definition (a big-endian uint64 of microseconds before each
// frame; MAVProxy's mavutil reads it so). tests/integration/gcs_relay_test.cc reads a run's log
// back with node-mavlink, a MAVLink implementation sitlnet did not write.
#include "gcs_link/tlog_writer.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

std::vector<uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A MAVLink 1 HEARTBEAT as the MAVLink 1 wire layout has it: magic, length 9, sequence, system,
// component, message id 0, 9 payload bytes, 2 checksum bytes (not checked by a tlog).
std::vector<uint8_t> Mavlink1Heartbeat() {
  std::vector<uint8_t> frame = {0xFE, 9, 0, 1, 1, 0};
  frame.resize(frame.size() + 9 + 2, 0);
  return frame;
}

TEST(TlogWriterTest, EachFrameOfADatagramFollowsItsBigEndianMicrosecondStamp) {
  const std::string path = ::testing::TempDir() + "/tlog_writer_test.tlog";
  std::vector<uint8_t> datagram;
  mavlink::AppendMessage(mavlink::Heartbeat{}, {7, 3, 1}, &datagram);
  const size_t v2_bytes = datagram.size();
  const std::vector<uint8_t> v1 = Mavlink1Heartbeat();
  datagram.insert(datagram.end(), v1.begin(), v1.end());
  datagram.push_back(0x55);  // Begins no frame.
  GcsRelayCounters counters;
  {
    TlogWriter tlog(path);
    // 0x0102030405 us and 999 ns: the stamp is rounded down to the microsecond.
    tlog.AppendDatagram(0x0102030405LL * kNsPerUs + 999, datagram.data(), datagram.size(),
                        &counters);
    tlog.Close();
  }
  EXPECT_EQ(counters.tlog_frames, 2u);
  EXPECT_EQ(counters.tlog_bytes_skipped, 1u);
  const std::vector<uint8_t> bytes = ReadBytes(path);
  ASSERT_EQ(bytes.size(), 8 + v2_bytes + 8 + v1.size());
  const std::vector<uint8_t> stamp = {0, 0, 0, 0x01, 0x02, 0x03, 0x04, 0x05};
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 8), stamp);
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 8, bytes.begin() + 8 + v2_bytes),
            std::vector<uint8_t>(datagram.begin(), datagram.begin() + v2_bytes));
  const size_t second = 8 + v2_bytes;
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + second, bytes.begin() + second + 8), stamp);
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + second + 8, bytes.end()), v1);
}

TEST(TlogWriterTest, AFrameCutShortIsSkippedNotWritten) {
  const std::string path = ::testing::TempDir() + "/tlog_writer_cut.tlog";
  std::vector<uint8_t> datagram;
  mavlink::AppendMessage(mavlink::Heartbeat{}, {7, 3, 1}, &datagram);
  datagram.pop_back();
  GcsRelayCounters counters;
  TlogWriter tlog(path);
  tlog.AppendDatagram(0, datagram.data(), datagram.size(), &counters);
  tlog.Close();
  EXPECT_EQ(counters.tlog_frames, 0u);
  EXPECT_EQ(counters.tlog_bytes_skipped, datagram.size());
  EXPECT_TRUE(ReadBytes(path).empty());
}

}  // namespace
}  // namespace sitlnet::gcs

// What a GCS sends is cut into whole frames; junk and cut frames are dropped and counted.
#include "gcs_link/frame_stream.h"

#include <gtest/gtest.h>

#include <vector>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

std::vector<uint8_t> HeartbeatFrame(uint8_t sequence) {
  std::vector<uint8_t> frame;
  mavlink::AppendMessage(mavlink::Heartbeat{}, {sequence, 255, 190}, &frame);
  return frame;
}

TEST(FrameStreamTest, JunkBetweenFramesIsDroppedAndCounted) {
  const std::vector<uint8_t> first = HeartbeatFrame(1), second = HeartbeatFrame(2);
  std::vector<uint8_t> bytes = {0x00, 0x11};
  bytes.insert(bytes.end(), first.begin(), first.end());
  bytes.insert(bytes.end(), {0x22, 0x33, 0x44});
  bytes.insert(bytes.end(), second.begin(), second.end());
  FrameStream stream;
  std::vector<uint8_t> frames;
  EXPECT_EQ(stream.Push(bytes.data(), bytes.size(), &frames), 2u);
  std::vector<uint8_t> expected = first;
  expected.insert(expected.end(), second.begin(), second.end());
  EXPECT_EQ(frames, expected);
  EXPECT_EQ(stream.bytes_dropped(), 5u);
}

TEST(FrameStreamTest, AFrameSpanningTwoReadsIsWholeOnceTheSecondArrives) {
  const std::vector<uint8_t> frame = HeartbeatFrame(7);
  FrameStream stream;
  std::vector<uint8_t> frames;
  EXPECT_EQ(stream.Push(frame.data(), 5, &frames), 0u);
  EXPECT_EQ(stream.Push(frame.data() + 5, frame.size() - 5, &frames), 1u);
  EXPECT_EQ(frames, frame);
  EXPECT_EQ(stream.bytes_dropped(), 0u);
}

TEST(FrameStreamTest, ADatagramsCutFrameIsDroppedAtItsEnd) {
  const std::vector<uint8_t> frame = HeartbeatFrame(7);
  FrameStream stream;
  std::vector<uint8_t> frames;
  EXPECT_EQ(stream.Push(frame.data(), frame.size() - 1, &frames), 0u);
  stream.DropRest();
  EXPECT_EQ(stream.bytes_dropped(), frame.size() - 1);
  EXPECT_EQ(stream.Push(frame.data(), frame.size(), &frames), 1u);  // The next one is whole.
  EXPECT_EQ(frames, frame);
}

}  // namespace
}  // namespace sitlnet::gcs

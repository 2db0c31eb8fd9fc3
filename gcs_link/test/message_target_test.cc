// The target table generated from mavlink-mappings, against common.xml's wire order: COMMAND_LONG
// is seven floats and a uint16 (30 bytes) before target_system (CRC_EXTRA 152 in mavlink.h's
// table, which mavlink/test/codec_test.cc derives from the same field list).
#include "gcs_link/message_target.h"

#include <gtest/gtest.h>

#include <vector>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

std::vector<uint8_t> CommandLong(uint8_t target_system, uint8_t target_component = 1) {
  mavlink::Payload payload{};
  payload[28] = 176;  // command (uint16 LE): MAV_CMD_DO_SET_MODE
  payload[30] = target_system;
  payload[31] = target_component;
  std::vector<uint8_t> frame;
  mavlink::AppendFrame(mavlink::kCommandLongId, payload.data(), {0, 255, 190}, &frame);
  return frame;
}

TEST(MessageTargetTest, CommandLongNamesItsTargetAndHeartbeatNone) {
  if (TargetTableSize() == 0) GTEST_SKIP() << "built without mavlink-mappings: nothing routed";
  EXPECT_EQ(TargetSystem(CommandLong(5).data()), 5);
  EXPECT_EQ(TargetSystem(CommandLong(0).data()), 0);  // broadcast
  std::vector<uint8_t> heartbeat;
  mavlink::AppendMessage(mavlink::Heartbeat{}, {0, 255, 190}, &heartbeat);
  EXPECT_EQ(TargetSystem(heartbeat.data()), std::nullopt);
}

TEST(MessageTargetTest, AFieldCutByZeroTruncationReadsZero) {
  if (TargetTableSize() == 0) GTEST_SKIP() << "built without mavlink-mappings: nothing routed";
  // Target and component zero: MAVLink 2 drops them, and the payload ends at the command.
  const std::vector<uint8_t> frame = CommandLong(0, 0);
  ASSERT_EQ(frame[1], 29);  // payload bytes: up to the command's low byte
  EXPECT_EQ(TargetSystem(frame.data()), 0);
}

}  // namespace
}  // namespace sitlnet::gcs

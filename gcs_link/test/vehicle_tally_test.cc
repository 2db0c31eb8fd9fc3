// Per-vehicle counts by MAVLink's header fields: a sequence number per sender that counts 0..255
// and wraps, so a jump of k + 1 means k frames missing; HEARTBEAT's base_mode carries
// MAV_MODE_FLAG_SAFETY_ARMED (128).
#include "gcs_link/vehicle_tally.h"

#include <gtest/gtest.h>

#include <vector>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

std::vector<uint8_t> Heartbeat(uint8_t sequence, uint8_t system, uint8_t type, uint8_t base_mode,
                               uint32_t custom_mode) {
  mavlink::Heartbeat heartbeat;
  heartbeat.type = type;
  heartbeat.autopilot = 3;  // MAV_AUTOPILOT_ARDUPILOTMEGA
  heartbeat.base_mode = base_mode;
  heartbeat.custom_mode = custom_mode;
  std::vector<uint8_t> frame;
  mavlink::AppendMessage(heartbeat, {sequence, system, 1}, &frame);
  return frame;
}

std::vector<uint8_t> Position(uint8_t sequence, uint8_t system, uint8_t component = 1) {
  std::vector<uint8_t> frame;
  mavlink::AppendMessage(mavlink::GlobalPositionInt{}, {sequence, system, component}, &frame);
  return frame;
}

void Count(VehicleTally* tally, const std::vector<uint8_t>& frame) {
  tally->Count(frame.data(), frame.size());
}

TEST(VehicleTallyTest, MessagesGapsAndTheLatestAutopilotHeartbeatPerSystem) {
  VehicleTally tally;
  Count(&tally, Heartbeat(0, 2, 2, 0, 0));
  Count(&tally, Position(1, 2));
  Count(&tally, Position(4, 2));                  // 2 and 3 missing
  Count(&tally, Heartbeat(5, 2, 2, 128 | 1, 4));  // armed, mode 4 (GUIDED)
  Count(&tally, Heartbeat(6, 2, 6, 0, 0));        // a GCS's own: not the vehicle's
  Count(&tally, Position(250, 2, 154));           // another component: its own count
  Count(&tally, Position(255, 7));
  Count(&tally, Position(0, 7));  // wraps: none missing
  const std::vector<VehicleCounters> vehicles = tally.vehicles();
  ASSERT_EQ(vehicles.size(), 2u);
  EXPECT_EQ(vehicles[0].system_id, 2);
  EXPECT_EQ(vehicles[0].messages, 6u);
  EXPECT_EQ(vehicles[0].sequence_gaps, 2u);
  EXPECT_TRUE(vehicles[0].heartbeat_seen);
  EXPECT_TRUE(vehicles[0].armed);
  EXPECT_EQ(vehicles[0].custom_mode, 4u);
  EXPECT_EQ(vehicles[0].type, 2);
  EXPECT_EQ(vehicles[1].system_id, 7);
  EXPECT_EQ(vehicles[1].messages, 2u);
  EXPECT_EQ(vehicles[1].sequence_gaps, 0u);
  EXPECT_FALSE(vehicles[1].heartbeat_seen);
}

TEST(VehicleTallyTest, AMavlink1HeartbeatIsReadByItsOwnLayout) {
  // MAVLink 1: magic, length, sequence, system, component, message id, payload, checksum.
  // HEARTBEAT's payload: custom_mode (uint32 LE), type, autopilot, base_mode, status, version.
  const uint8_t frame[] = {0xFE, 9, 10, 9, 1, 0, 5, 0, 0, 0, 2, 3, 128, 4, 3, 0xAA, 0xBB};
  VehicleTally tally;
  tally.Count(frame, sizeof frame);
  const std::vector<VehicleCounters> vehicles = tally.vehicles();
  ASSERT_EQ(vehicles.size(), 1u);
  EXPECT_EQ(vehicles[0].system_id, 9);
  EXPECT_TRUE(vehicles[0].armed);
  EXPECT_EQ(vehicles[0].custom_mode, 5u);
}

// The view names a vehicle's robot by the address its frames came from: the first one heard.
TEST(VehicleTallyTest, EachSystemKeepsTheAddressOfItsFirstDatagram) {
  VehicleTally tally;
  const std::vector<uint8_t> first = Position(0, 2), later = Position(1, 2), other = Position(0, 3);
  tally.Count(first.data(), first.size(), Ipv4{0x0A4D0002});
  tally.Count(later.data(), later.size(), Ipv4{0x0A4D0009});
  tally.Count(other.data(), other.size(), Ipv4{0x0A4D0003});
  const std::vector<VehicleCounters> vehicles = tally.vehicles();
  ASSERT_EQ(vehicles.size(), 2u);
  EXPECT_EQ(FormatIpv4(vehicles[0].address), "10.77.0.2");
  EXPECT_EQ(FormatIpv4(vehicles[1].address), "10.77.0.3");
}

}  // namespace
}  // namespace sitlnet::gcs

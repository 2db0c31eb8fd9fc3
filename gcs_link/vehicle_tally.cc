#include "gcs_link/vehicle_tally.h"

#include <algorithm>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

constexpr uint8_t kMavTypeGcs = 6;           // MAV_TYPE_GCS (common.xml)
constexpr uint8_t kMavAutopilotInvalid = 8;  // MAV_AUTOPILOT_INVALID: not a flight controller
constexpr size_t kHeartbeatPayloadBytes = 9;

struct FrameHeader {
  uint8_t sequence = 0, system_id = 0, component_id = 0;
  uint32_t message_id = 0;
  const uint8_t* payload = nullptr;
  size_t payload_bytes = 0;
};

// The header fields by each version's layout (MAVLink's serialization page).
FrameHeader ReadHeader(const uint8_t* frame) {
  FrameHeader header;
  header.payload_bytes = frame[1];
  if (frame[0] == mavlink::kMagicV1) {
    header.sequence = frame[2];
    header.system_id = frame[3];
    header.component_id = frame[4];
    header.message_id = frame[5];
    header.payload = frame + mavlink::kHeaderV1Bytes;
  } else {
    header.sequence = frame[4];
    header.system_id = frame[5];
    header.component_id = frame[6];
    header.message_id = frame[7] | (frame[8] << 8) | (static_cast<uint32_t>(frame[9]) << 16);
    header.payload = frame + mavlink::kHeaderV2Bytes;
  }
  return header;
}

}  // namespace

void VehicleTally::Count(const uint8_t* frame, size_t /*bytes*/, Ipv4 sender) {
  const FrameHeader header = ReadHeader(frame);
  auto [at, inserted] = vehicles_.try_emplace(header.system_id);
  Vehicle& vehicle = at->second;
  if (inserted) {
    vehicle.counters.system_id = header.system_id;
    vehicle.counters.address = sender;
    vehicle.last_sequence.fill(-1);
  }
  ++vehicle.counters.messages;
  int& last = vehicle.last_sequence[header.component_id];
  if (last >= 0) vehicle.counters.sequence_gaps += (header.sequence - last - 1) & 0xFF;
  last = header.sequence;
  if (header.message_id != mavlink::kHeartbeatId) return;
  // MAVLink 2 drops the payload's trailing zeros: what is missing is zero.
  uint8_t payload[kHeartbeatPayloadBytes] = {};
  std::copy_n(header.payload, std::min(header.payload_bytes, sizeof payload), payload);
  const uint8_t type = payload[4], autopilot = payload[5];
  if (type == kMavTypeGcs || autopilot == kMavAutopilotInvalid) return;
  VehicleCounters& counters = vehicle.counters;
  counters.heartbeat_seen = true;
  counters.custom_mode = payload[0] | (payload[1] << 8) | (payload[2] << 16) |
                         (static_cast<uint32_t>(payload[3]) << 24);
  counters.type = type;
  counters.autopilot = autopilot;
  counters.base_mode = payload[6];
  counters.armed = (payload[6] & mavlink::kModeFlagSafetyArmed) != 0;
}

std::vector<VehicleCounters> VehicleTally::vehicles() const {
  std::vector<VehicleCounters> out;
  for (const auto& [id, vehicle] : vehicles_) out.push_back(vehicle.counters);
  return out;
}

}  // namespace sitlnet::gcs

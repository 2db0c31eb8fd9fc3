// The MAVLink messages of PX4's simulator interface, packed in MAVLink's wire order (fields
// sorted by type size, then extensions; docs/references.md#mavlink). Units as in common.xml.
#ifndef SITLNET_PHYSICS_MUJOCO_MAVLINK_MESSAGES_H_
#define SITLNET_PHYSICS_MUJOCO_MAVLINK_MESSAGES_H_

#include <array>
#include <cstdint>

#include "physics_mujoco/mavlink_codec.h"

namespace sitlnet::physics::mavlink {

inline constexpr uint8_t kModeFlagSafetyArmed = 128;       // MAV_MODE_FLAG_SAFETY_ARMED
inline constexpr uint64_t kActuatorFlagLockstep = 1;       // HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP
inline constexpr uint32_t kSensorUpdatedAccelGyro = 0x3F;  // HIL_SENSOR_UPDATED_X/Y/ZACC, GYRO
inline constexpr uint32_t kSensorUpdatedMag = 0x1C0;       // X/Y/ZMAG
inline constexpr uint32_t kSensorUpdatedBaro = 0x1A00;  // ABS_PRESSURE, PRESSURE_ALT, TEMPERATURE
inline constexpr uint16_t kUnknownU16 = 0xFFFF;         // UINT16_MAX: "unknown" in HIL_GPS

struct Heartbeat {  // 0
  uint32_t custom_mode = 0;
  uint8_t type = 0;       // MAV_TYPE
  uint8_t autopilot = 0;  // MAV_AUTOPILOT
  uint8_t base_mode = 0;  // MAV_MODE_FLAG bits
  uint8_t system_status = 0;
  uint8_t mavlink_version = 3;
};

struct HilActuatorControls {  // 93
  uint64_t time_usec = 0;
  uint64_t flags = 0;
  std::array<float, 16> controls{};  // PX4: motor outputs 0..1
  uint8_t mode = 0;                  // MAV_MODE_FLAG bits
};

struct HilSensor {  // 107
  uint64_t time_usec = 0;
  float xacc = 0, yacc = 0, zacc = 0;     // m/s^2, body FRD
  float xgyro = 0, ygyro = 0, zgyro = 0;  // rad/s, body FRD
  float xmag = 0, ymag = 0, zmag = 0;     // gauss, body FRD
  float abs_pressure = 0;                 // hPa
  float diff_pressure = 0;                // hPa
  float pressure_alt = 0;                 // m
  float temperature = 0;                  // degC
  uint32_t fields_updated = 0;            // HIL_SENSOR_UPDATED_* bits
  uint8_t id = 0;                         // extension
};

struct HilGps {  // 113
  uint64_t time_usec = 0;
  int32_t lat = 0, lon = 0;  // degE7
  int32_t alt = 0;           // mm above MSL
  uint16_t eph = kUnknownU16, epv = kUnknownU16;
  uint16_t vel = kUnknownU16;      // cm/s ground speed
  int16_t vn = 0, ve = 0, vd = 0;  // cm/s NED
  uint16_t cog = kUnknownU16;      // cdeg
  uint8_t fix_type = 0;
  uint8_t satellites_visible = 0xFF;
  uint8_t id = 0;    // extension
  uint16_t yaw = 0;  // extension, cdeg; 0: not available
};

struct HilStateQuaternion {  // 115
  uint64_t time_usec = 0;
  std::array<float, 4> attitude_quaternion{1, 0, 0, 0};  // w, x, y, z: body FRD in NED
  float rollspeed = 0, pitchspeed = 0, yawspeed = 0;     // rad/s, body FRD
  int32_t lat = 0, lon = 0, alt = 0;                     // degE7, degE7, mm
  int16_t vx = 0, vy = 0, vz = 0;                        // cm/s, north, east, down
  uint16_t ind_airspeed = 0, true_airspeed = 0;          // cm/s
  int16_t xacc = 0, yacc = 0, zacc = 0;                  // mG, body FRD
};

// Payload of each message, max_length bytes in wire order.
using Payload = std::array<uint8_t, kMaxPayloadBytes>;
Payload Pack(const Heartbeat& message);
Payload Pack(const HilActuatorControls& message);
Payload Pack(const HilSensor& message);
Payload Pack(const HilGps& message);
Payload Pack(const HilStateQuaternion& message);

// Decodes a frame of the matching id; false for another id.
bool Unpack(const ReceivedFrame& frame, Heartbeat* message);
bool Unpack(const ReceivedFrame& frame, HilActuatorControls* message);
bool Unpack(const ReceivedFrame& frame, HilSensor* message);
bool Unpack(const ReceivedFrame& frame, HilGps* message);
bool Unpack(const ReceivedFrame& frame, HilStateQuaternion* message);

// Message id of each type, for AppendFrame.
constexpr uint32_t IdOf(const Heartbeat&) { return kHeartbeatId; }
constexpr uint32_t IdOf(const HilActuatorControls&) { return kHilActuatorControlsId; }
constexpr uint32_t IdOf(const HilSensor&) { return kHilSensorId; }
constexpr uint32_t IdOf(const HilGps&) { return kHilGpsId; }
constexpr uint32_t IdOf(const HilStateQuaternion&) { return kHilStateQuaternionId; }

// Packs `message` and appends its frame to `out`.
template <typename Message>
void AppendMessage(const Message& message, const Header& header, std::vector<uint8_t>* out) {
  const Payload payload = Pack(message);
  AppendFrame(IdOf(message), payload.data(), header, out);
}

}  // namespace sitlnet::physics::mavlink

#endif  // SITLNET_PHYSICS_MUJOCO_MAVLINK_MESSAGES_H_

// MAVLink 2 (docs/references.md#mavlink): framing (the X.25 CRC with each message's CRC_EXTRA,
// zero-truncated payloads, a stream parser that resynchronizes on garbage) and the messages
// sitlnet speaks: PX4's simulator interface and the telemetry an autopilot sends a ground
// station, packed in MAVLink's wire order (fields sorted by type size, then extensions). Units
// as in common.xml. Other messages are counted and skipped. Used by the physics server (PX4's
// simulator link) and by sitlnet's test autopilot.
#ifndef SITLNET_MAVLINK_MAVLINK_H_
#define SITLNET_MAVLINK_MAVLINK_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sitlnet::mavlink {

inline constexpr uint8_t kMagicV2 = 0xFD;
inline constexpr uint8_t kMagicV1 = 0xFE;
inline constexpr size_t kHeaderV2Bytes = 10;  // magic .. 24-bit message id
inline constexpr size_t kHeaderV1Bytes = 6;
inline constexpr size_t kChecksumBytes = 2;
inline constexpr size_t kSignatureBytes = 13;
inline constexpr uint8_t kIncompatSigned = 0x01;
inline constexpr size_t kMaxPayloadBytes = 255;

// Message ids (common.xml, minimal.xml).
inline constexpr uint32_t kHeartbeatId = 0;
inline constexpr uint32_t kGlobalPositionIntId = 33;
inline constexpr uint32_t kCommandLongId = 76;
inline constexpr uint32_t kHilActuatorControlsId = 93;
inline constexpr uint32_t kHilSensorId = 107;
inline constexpr uint32_t kHilGpsId = 113;
inline constexpr uint32_t kHilStateQuaternionId = 115;

// CRC-16/MCRF4XX ("X.25" in MAVLink's sources) of `size` bytes, continuing from `crc`.
uint16_t Crc16(const uint8_t* data, size_t size, uint16_t crc = 0xFFFF);

struct MessageInfo {
  uint32_t id = 0;
  uint8_t crc_extra = 0;
  uint8_t base_length = 0;  // Payload bytes without extensions.
  uint8_t max_length = 0;   // With extensions.
};
// The message with `id`, or nullptr if sitlnet does not know it.
const MessageInfo* FindMessage(uint32_t id);

struct Header {
  uint8_t sequence = 0;
  uint8_t system_id = 0;
  uint8_t component_id = 0;
};

// Appends one MAVLink 2 frame (unsigned) of message `id` to `out`: trailing zero bytes of the
// payload removed (one byte always stays), CRC over header and payload plus CRC_EXTRA.
// `payload` holds the full max_length bytes of the message. Demands a known id.
void AppendFrame(uint32_t id, const uint8_t* payload, const Header& header,
                 std::vector<uint8_t>* out);

// Bytes of the MAVLink 1 or 2 frame that starts at `data` (magic byte, header, payload,
// checksum, and a MAVLink 2 signature when its incompat flag says so), from its header alone:
// any message id, no checksum checked. 0 if `data` starts with no magic byte or holds less.
// For a relay and a telemetry log, which split datagrams into frames and judge none.
size_t FrameBytes(const uint8_t* data, size_t size);

// A received frame, its payload zero-filled to the message's max_length.
struct ReceivedFrame {
  uint32_t message_id = 0;
  Header header;
  std::array<uint8_t, kMaxPayloadBytes> payload{};
};

// What the parser found besides valid frames. A byte that begins no valid frame is skipped and
// counted once: as the start of a frame that failed (bad_crc, bad_length), as the magic byte of
// a message sitlnet cannot check (unknown_messages, mavlink1_frames), or else as bytes_skipped.
struct ParserCounters {
  uint64_t frames = 0;            // Valid frames of known messages.
  uint64_t bytes_skipped = 0;     // Other bytes that began no frame (garbage, a failed frame's).
  uint64_t bad_crc = 0;           // Known message, checksum wrong.
  uint64_t bad_length = 0;        // Known message, payload longer than the message or empty.
  uint64_t unknown_messages = 0;  // MAVLink 2 header of a message sitlnet does not know.
  uint64_t mavlink1_frames = 0;   // MAVLink 1 magic bytes (0xFE).
};

// Splits a byte stream (TCP) into frames. Bytes that cannot begin a valid frame are skipped
// one at a time until the next magic byte, so a corrupted or unknown frame costs no valid one
// after it (only a frame that passes its CRC is consumed whole).
class FrameParser {
 public:
  void Push(const uint8_t* data, size_t size);
  // Takes the next valid frame, if a whole one has arrived.
  bool Next(ReceivedFrame* frame);
  void Reset();
  const ParserCounters& counters() const { return counters_; }

 private:
  std::vector<uint8_t> buffer_;
  size_t start_ = 0;  // First unparsed byte of buffer_.
  ParserCounters counters_;
};

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

struct GlobalPositionInt {  // 33: an autopilot's fused position, for ground stations
  uint32_t time_boot_ms = 0;
  int32_t lat = 0, lon = 0;        // degE7
  int32_t alt = 0;                 // mm above MSL
  int32_t relative_alt = 0;        // mm above home
  int16_t vx = 0, vy = 0, vz = 0;  // cm/s, north, east, down
  uint16_t hdg = kUnknownU16;      // cdeg, 0..35999
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
Payload Pack(const GlobalPositionInt& message);
Payload Pack(const HilActuatorControls& message);
Payload Pack(const HilSensor& message);
Payload Pack(const HilGps& message);
Payload Pack(const HilStateQuaternion& message);

// Decodes a frame of the matching id; false for another id.
bool Unpack(const ReceivedFrame& frame, Heartbeat* message);
bool Unpack(const ReceivedFrame& frame, GlobalPositionInt* message);
bool Unpack(const ReceivedFrame& frame, HilActuatorControls* message);
bool Unpack(const ReceivedFrame& frame, HilSensor* message);
bool Unpack(const ReceivedFrame& frame, HilGps* message);
bool Unpack(const ReceivedFrame& frame, HilStateQuaternion* message);

// Message id of each type, for AppendFrame.
constexpr uint32_t IdOf(const Heartbeat&) { return kHeartbeatId; }
constexpr uint32_t IdOf(const GlobalPositionInt&) { return kGlobalPositionIntId; }
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

}  // namespace sitlnet::mavlink

#endif  // SITLNET_MAVLINK_MAVLINK_H_

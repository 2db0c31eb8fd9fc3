// MAVLink 2 framing (docs/references.md#mavlink): the X.25 CRC with each message's CRC_EXTRA,
// zero-truncated payloads, and a stream parser that resynchronizes on garbage. Only the
// messages of PX4's simulator interface are known; the rest are counted and skipped.
#ifndef SITLNET_PHYSICS_MUJOCO_MAVLINK_CODEC_H_
#define SITLNET_PHYSICS_MUJOCO_MAVLINK_CODEC_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sitlnet::physics::mavlink {

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

}  // namespace sitlnet::physics::mavlink

#endif  // SITLNET_PHYSICS_MUJOCO_MAVLINK_CODEC_H_

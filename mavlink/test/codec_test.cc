// MAVLink 2 framing against the CRC catalogue, common.xml's field lists and hand-made streams.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "mavlink/mavlink.h"

namespace sitlnet::mavlink {
namespace {

TEST(MavlinkCrcTest, CheckValueOfTheCatalogue) {
  // CRC-16/MCRF4XX, check value of "123456789" (Greg Cook's catalogue of parametrised CRCs).
  const std::string text = "123456789";
  EXPECT_EQ(Crc16(reinterpret_cast<const uint8_t*>(text.data()), text.size()), 0x6F91);
}

// A field of common.xml: type without array suffix, name, array length (0: scalar).
struct Field {
  std::string type, name;
  int array = 0;
};

int SizeOf(const std::string& type) {
  static const std::map<std::string, int> sizes = {
      {"uint64_t", 8}, {"int64_t", 8},  {"double", 8},  {"uint32_t", 4}, {"int32_t", 4},
      {"float", 4},    {"uint16_t", 2}, {"int16_t", 2}, {"uint8_t", 1},  {"int8_t", 1}};
  return sizes.at(type);
}

// CRC_EXTRA by MAVLink's rule, from the fields in XML order (sorted here, stable, by size).
uint8_t CrcExtraOf(const std::string& name, std::vector<Field> fields) {
  std::stable_sort(fields.begin(), fields.end(),
                   [](const Field& a, const Field& b) { return SizeOf(a.type) > SizeOf(b.type); });
  auto add = [](uint16_t crc, const std::string& text) {
    return Crc16(reinterpret_cast<const uint8_t*>(text.data()), text.size(), crc);
  };
  uint16_t crc = add(0xFFFF, name + " ");
  for (const Field& field : fields) {
    crc = add(crc, field.type + " ");
    crc = add(crc, field.name + " ");
    if (field.array > 0) {
      const uint8_t length = static_cast<uint8_t>(field.array);
      crc = Crc16(&length, 1, crc);
    }
  }
  return static_cast<uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

int LengthOf(const std::vector<Field>& fields) {
  int length = 0;
  for (const Field& field : fields) length += SizeOf(field.type) * std::max(1, field.array);
  return length;
}

TEST(MavlinkCodecTest, CrcExtraAndLengthsFollowFromCommonXml) {
  // The base fields of each message, transcribed in XML order from common.xml / minimal.xml
  // (HEARTBEAT's mavlink_version is uint8_t_mavlink_version, hashed as uint8_t).
  const struct {
    uint32_t id;
    std::string name;
    std::vector<Field> base;
    int extension_bytes;
  } messages[] = {
      {kHeartbeatId,
       "HEARTBEAT",
       {{"uint8_t", "type"},
        {"uint8_t", "autopilot"},
        {"uint8_t", "base_mode"},
        {"uint32_t", "custom_mode"},
        {"uint8_t", "system_status"},
        {"uint8_t", "mavlink_version"}},
       0},
      {kGlobalPositionIntId,
       "GLOBAL_POSITION_INT",
       {{"uint32_t", "time_boot_ms"},
        {"int32_t", "lat"},
        {"int32_t", "lon"},
        {"int32_t", "alt"},
        {"int32_t", "relative_alt"},
        {"int16_t", "vx"},
        {"int16_t", "vy"},
        {"int16_t", "vz"},
        {"uint16_t", "hdg"}},
       0},
      {kCommandLongId,
       "COMMAND_LONG",
       {{"uint8_t", "target_system"},
        {"uint8_t", "target_component"},
        {"uint16_t", "command"},
        {"uint8_t", "confirmation"},
        {"float", "param1"},
        {"float", "param2"},
        {"float", "param3"},
        {"float", "param4"},
        {"float", "param5"},
        {"float", "param6"},
        {"float", "param7"}},
       0},
      {kHilActuatorControlsId,
       "HIL_ACTUATOR_CONTROLS",
       {{"uint64_t", "time_usec"},
        {"float", "controls", 16},
        {"uint8_t", "mode"},
        {"uint64_t", "flags"}},
       0},
      {kHilSensorId,
       "HIL_SENSOR",
       {{"uint64_t", "time_usec"},
        {"float", "xacc"},
        {"float", "yacc"},
        {"float", "zacc"},
        {"float", "xgyro"},
        {"float", "ygyro"},
        {"float", "zgyro"},
        {"float", "xmag"},
        {"float", "ymag"},
        {"float", "zmag"},
        {"float", "abs_pressure"},
        {"float", "diff_pressure"},
        {"float", "pressure_alt"},
        {"float", "temperature"},
        {"uint32_t", "fields_updated"}},
       1},  // id
      {kHilGpsId,
       "HIL_GPS",
       {{"uint64_t", "time_usec"},
        {"uint8_t", "fix_type"},
        {"int32_t", "lat"},
        {"int32_t", "lon"},
        {"int32_t", "alt"},
        {"uint16_t", "eph"},
        {"uint16_t", "epv"},
        {"uint16_t", "vel"},
        {"int16_t", "vn"},
        {"int16_t", "ve"},
        {"int16_t", "vd"},
        {"uint16_t", "cog"},
        {"uint8_t", "satellites_visible"}},
       3},  // id, yaw
      {kHilStateQuaternionId,
       "HIL_STATE_QUATERNION",
       {{"uint64_t", "time_usec"},
        {"float", "attitude_quaternion", 4},
        {"float", "rollspeed"},
        {"float", "pitchspeed"},
        {"float", "yawspeed"},
        {"int32_t", "lat"},
        {"int32_t", "lon"},
        {"int32_t", "alt"},
        {"int16_t", "vx"},
        {"int16_t", "vy"},
        {"int16_t", "vz"},
        {"uint16_t", "ind_airspeed"},
        {"uint16_t", "true_airspeed"},
        {"int16_t", "xacc"},
        {"int16_t", "yacc"},
        {"int16_t", "zacc"}},
       0},
  };
  for (const auto& message : messages) {
    const MessageInfo* info = FindMessage(message.id);
    ASSERT_NE(info, nullptr) << message.name;
    EXPECT_EQ(info->crc_extra, CrcExtraOf(message.name, message.base)) << message.name;
    EXPECT_EQ(info->base_length, LengthOf(message.base)) << message.name;
    EXPECT_EQ(info->max_length, LengthOf(message.base) + message.extension_bytes) << message.name;
  }
  // Values published in MAVLink's generated C headers, for the record: 50, 152, 47, 108, 124, 4.
  EXPECT_EQ(FindMessage(kHilSensorId)->crc_extra, 108);
  EXPECT_EQ(FindMessage(9999), nullptr);
}

TEST(MavlinkCodecTest, WireOrderIsBySizeThenExtensions) {
  HilActuatorControls controls;
  controls.time_usec = 0x0102030405060708;
  controls.flags = 1;
  controls.controls[0] = 1.0f;  // 0x3F800000
  controls.mode = 129;
  const Payload p = Pack(controls);
  EXPECT_EQ(p[0], 0x08);   // time_usec, little-endian
  EXPECT_EQ(p[8], 0x01);   // flags (uint64) before the float array
  EXPECT_EQ(p[19], 0x3F);  // controls[0], bytes 16..19
  EXPECT_EQ(p[80], 129);   // mode last
  HilGps gps;
  gps.satellites_visible = 7;
  gps.id = 2;
  gps.yaw = 0x1234;
  const Payload g = Pack(gps);
  EXPECT_EQ(g[35], 7);  // last base field
  EXPECT_EQ(g[36], 2);  // extensions in XML order
  EXPECT_EQ(g[37], 0x34);
  EXPECT_EQ(g[38], 0x12);
}

std::vector<uint8_t> FrameOf(const HilSensor& sensor, uint8_t sequence = 0) {
  std::vector<uint8_t> bytes;
  AppendMessage(sensor, {sequence, 1, 200}, &bytes);
  return bytes;
}

TEST(MavlinkCodecTest, TrailingZerosAreTruncatedAndRestored) {
  HilSensor sensor;
  sensor.time_usec = 42;
  sensor.fields_updated = 0x3F;  // ends at byte 61; id 0 and the upper bytes are zeros
  const std::vector<uint8_t> bytes = FrameOf(sensor);
  EXPECT_EQ(bytes[1], 61);  // payload length sent
  EXPECT_EQ(bytes.size(), kHeaderV2Bytes + 61 + kChecksumBytes);
  FrameParser parser;
  parser.Push(bytes.data(), bytes.size());
  ReceivedFrame frame;
  ASSERT_TRUE(parser.Next(&frame));
  HilSensor back;
  ASSERT_TRUE(Unpack(frame, &back));
  EXPECT_EQ(back.time_usec, 42u);
  EXPECT_EQ(back.fields_updated, 0x3Fu);
  EXPECT_EQ(back.id, 0);
  // An all-zero payload keeps one byte.
  std::vector<uint8_t> zero;
  AppendMessage(Heartbeat{0, 0, 0, 0, 0, 0}, {}, &zero);
  EXPECT_EQ(zero[1], 1);
}

TEST(MavlinkCodecTest, ParserSkipsGarbageCorruptionUnknownAndMavlink1) {
  HilSensor sensor;
  sensor.time_usec = 7;
  sensor.xacc = 1.5f;
  std::vector<uint8_t> stream = {0x00, 0x11, 0xFD};  // garbage, then a lone magic byte
  std::vector<uint8_t> corrupted = FrameOf(sensor, 1);
  corrupted[12] ^= 0xFF;  // a payload byte: CRC fails
  stream.insert(stream.end(), corrupted.begin(), corrupted.end());
  // An unknown message id 9999 (CRC not checkable), skipped whole.
  const std::vector<uint8_t> unknown = {0xFD, 2,    0,    0,    5,    1,    1,
                                        0x0F, 0x27, 0x00, 0xFD, 0xFD, 0xAA, 0xBB};
  stream.insert(stream.end(), unknown.begin(), unknown.end());
  // A MAVLink 1 heartbeat (9-byte payload), skipped whole.
  const std::vector<uint8_t> v1 = {0xFE, 9, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0xAA, 0xBB};
  stream.insert(stream.end(), v1.begin(), v1.end());
  const std::vector<uint8_t> good = FrameOf(sensor, 2);
  stream.insert(stream.end(), good.begin(), good.end());

  // Byte by byte: framing must not depend on how TCP splits the stream.
  FrameParser parser;
  std::vector<ReceivedFrame> frames;
  for (uint8_t byte : stream) {
    parser.Push(&byte, 1);
    ReceivedFrame frame;
    while (parser.Next(&frame)) frames.push_back(frame);
  }
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].header.sequence, 2);
  HilSensor back;
  ASSERT_TRUE(Unpack(frames[0], &back));
  EXPECT_EQ(back.xacc, 1.5f);
  const ParserCounters& counters = parser.counters();
  EXPECT_EQ(counters.frames, 1u);
  EXPECT_GE(counters.bad_crc + counters.bad_length, 1u);
  EXPECT_GE(counters.unknown_messages, 1u);
  EXPECT_EQ(counters.mavlink1_frames, 1u);
  // Every byte before the good frame was skipped once, under one counter or another.
  EXPECT_EQ(counters.bytes_skipped + counters.bad_crc + counters.bad_length +
                counters.unknown_messages + counters.mavlink1_frames,
            stream.size() - good.size());
}

TEST(MavlinkCodecTest, CorruptedFrameCostsNoFollowingFrame) {
  HilSensor sensor;
  sensor.time_usec = 9;
  sensor.fields_updated = 0x3F;  // a 61-byte payload
  std::vector<uint8_t> stream = FrameOf(sensor, 1);
  stream.resize(stream.size() - 5);  // cut short: its CRC now covers the next frame's bytes
  const std::vector<uint8_t> good = FrameOf(sensor, 2);
  stream.insert(stream.end(), good.begin(), good.end());
  FrameParser parser;
  parser.Push(stream.data(), stream.size());
  ReceivedFrame frame;
  ASSERT_TRUE(parser.Next(&frame));
  EXPECT_EQ(frame.header.sequence, 2);
  EXPECT_FALSE(parser.Next(&frame));
  EXPECT_EQ(parser.counters().bad_crc, 1u);
}

}  // namespace
}  // namespace sitlnet::mavlink

namespace sitlnet::mavlink {
namespace {

// Frame lengths from the headers' layout (MAVLink's serialization page): MAVLink 1 is 8 bytes
// around its payload, MAVLink 2 is 12, and 13 more when incompat_flags has MAVLINK_IFLAG_SIGNED.
TEST(MavlinkCodecTest, FrameBytesFollowsTheHeaderOfEitherVersion) {
  std::vector<uint8_t> v2;
  AppendMessage(Heartbeat{}, {1, 2, 3}, &v2);
  EXPECT_EQ(FrameBytes(v2.data(), v2.size()), v2.size());
  EXPECT_EQ(FrameBytes(v2.data(), v2.size() - 1), 0u);
  std::vector<uint8_t> signed_v2 = v2;
  signed_v2[2] |= kIncompatSigned;
  signed_v2.resize(v2.size() + kSignatureBytes);
  EXPECT_EQ(FrameBytes(signed_v2.data(), signed_v2.size()), v2.size() + 13);
  const uint8_t v1[] = {0xFE, 9, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xAA};
  EXPECT_EQ(FrameBytes(v1, sizeof v1), 17u);
  const uint8_t garbage[] = {0x00, 0xFD, 0x01};
  EXPECT_EQ(FrameBytes(garbage, sizeof garbage), 0u);
}

}  // namespace
}  // namespace sitlnet::mavlink

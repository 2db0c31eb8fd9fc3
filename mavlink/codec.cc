#include <algorithm>
#include <cstring>

#include "common/common.h"
#include "mavlink/mavlink.h"

namespace sitlnet::mavlink {
namespace {

// CRC_EXTRA and lengths: computed from common.xml / minimal.xml by MAVLink's rule
// (docs/references.md#mavlink); mavlink/test/codec_test.cc derives them again from the field lists.
constexpr MessageInfo kMessages[] = {
    {kHeartbeatId, 50, 9, 9},           {kGlobalPositionIntId, 104, 28, 28},
    {kCommandLongId, 152, 33, 33},      {kHilActuatorControlsId, 47, 81, 81},
    {kHilSensorId, 108, 64, 65},        {kHilGpsId, 124, 36, 39},
    {kHilStateQuaternionId, 4, 64, 64},
};

}  // namespace

uint16_t Crc16(const uint8_t* data, size_t size, uint16_t crc) {
  for (size_t i = 0; i < size; ++i) {
    uint8_t t = static_cast<uint8_t>(data[i] ^ (crc & 0xFF));
    t ^= static_cast<uint8_t>(t << 4);
    crc = static_cast<uint16_t>((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
  }
  return crc;
}

const MessageInfo* FindMessage(uint32_t id) {
  for (const MessageInfo& info : kMessages) {
    if (info.id == id) return &info;
  }
  return nullptr;
}

size_t FrameBytes(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  size_t bytes = 0;
  if (data[0] == kMagicV1) {
    bytes = kHeaderV1Bytes + data[1] + kChecksumBytes;
  } else if (data[0] == kMagicV2) {
    bytes = kHeaderV2Bytes + data[1] + kChecksumBytes +
            ((data[2] & kIncompatSigned) ? kSignatureBytes : 0);
  }
  return bytes <= size ? bytes : 0;
}

void AppendFrame(uint32_t id, const uint8_t* payload, const Header& header,
                 std::vector<uint8_t>* out) {
  const MessageInfo* info = FindMessage(id);
  SITLNET_DEMAND(info != nullptr);
  size_t length = info->max_length;
  while (length > 1 && payload[length - 1] == 0) --length;
  const size_t begin = out->size();
  const uint8_t head[kHeaderV2Bytes] = {kMagicV2,
                                        static_cast<uint8_t>(length),
                                        0,
                                        0,
                                        header.sequence,
                                        header.system_id,
                                        header.component_id,
                                        static_cast<uint8_t>(id),
                                        static_cast<uint8_t>(id >> 8),
                                        static_cast<uint8_t>(id >> 16)};
  out->insert(out->end(), head, head + kHeaderV2Bytes);
  out->insert(out->end(), payload, payload + length);
  uint16_t crc = Crc16(out->data() + begin + 1, kHeaderV2Bytes - 1 + length);
  crc = Crc16(&info->crc_extra, 1, crc);
  out->push_back(static_cast<uint8_t>(crc));
  out->push_back(static_cast<uint8_t>(crc >> 8));
}

void FrameParser::Push(const uint8_t* data, size_t size) {
  // Drop what was parsed before growing, so the buffer stays as small as one frame or two.
  if (start_ > 0) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
  buffer_.insert(buffer_.end(), data, data + size);
}

void FrameParser::Reset() {
  buffer_.clear();
  start_ = 0;
}

bool FrameParser::Next(ReceivedFrame* frame) {
  while (start_ < buffer_.size()) {
    const uint8_t* p = buffer_.data() + start_;
    const size_t available = buffer_.size() - start_;
    if (p[0] == kMagicV1) {
      // MAVLink 1 (PX4's simulator module speaks MAVLink 2): counted and skipped like garbage,
      // one byte at a time, so a stray 0xFE cannot swallow the frames after it.
      ++counters_.mavlink1_frames;
      ++start_;
      continue;
    }
    if (p[0] != kMagicV2) {
      ++counters_.bytes_skipped;
      ++start_;
      continue;
    }
    if (available < kHeaderV2Bytes) return false;
    const size_t length = p[1];
    const bool is_signed = (p[2] & kIncompatSigned) != 0;
    const uint32_t id = uint32_t{p[7]} | (uint32_t{p[8]} << 8) | (uint32_t{p[9]} << 16);
    const MessageInfo* info = FindMessage(id);
    if (info == nullptr) {
      // Cannot be checked without its CRC_EXTRA, so its length cannot be trusted either: skipped
      // one byte at a time, so a stray 0xFD cannot swallow the frames after it.
      ++counters_.unknown_messages;
      ++start_;
      continue;
    }
    if (length == 0 || length > info->max_length) {
      ++counters_.bad_length;
      ++start_;
      continue;
    }
    const size_t total =
        kHeaderV2Bytes + length + kChecksumBytes + (is_signed ? kSignatureBytes : 0);
    if (available < total) return false;
    uint16_t crc = Crc16(p + 1, kHeaderV2Bytes - 1 + length);
    crc = Crc16(&info->crc_extra, 1, crc);
    const uint16_t sent =
        static_cast<uint16_t>(p[kHeaderV2Bytes + length] | (p[kHeaderV2Bytes + length + 1] << 8));
    if (crc != sent) {
      ++counters_.bad_crc;
      ++start_;  // Resynchronize at the next magic byte: a real frame may start inside.
      continue;
    }
    frame->message_id = id;
    frame->header = {p[4], p[5], p[6]};
    frame->payload.fill(0);
    std::memcpy(frame->payload.data(), p + kHeaderV2Bytes, length);
    ++counters_.frames;
    start_ += total;  // A signature, if any, is skipped unchecked.
    return true;
  }
  return false;
}

}  // namespace sitlnet::mavlink

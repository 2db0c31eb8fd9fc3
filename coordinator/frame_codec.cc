#include "coordinator/frame_codec.h"

#include <zlib.h>

#include <cstring>

#include "common/common.h"

namespace sitlnet::coordinator {
namespace {

void PutLe32(uint8_t* out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<uint8_t>(value >> (8 * i));
}

uint32_t GetLe32(const uint8_t* in) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= uint32_t{in[i]} << (8 * i);
  return value;
}

std::string TooLong(std::string_view what, size_t bytes, size_t limit) {
  return "bad frame: " + std::string(what) + " of " + std::to_string(bytes) +
         " bytes exceeds the limit of " + std::to_string(limit) + " bytes";
}

}  // namespace

std::string_view FrameEncoder::Encode(const proto::coord::CoordinatorMessage& message) {
  const size_t raw_bytes = message.ByteSizeLong();
  if (raw_bytes > options_.max_frame_bytes) {
    throw Error(TooLong("message", raw_bytes, options_.max_frame_bytes));
  }
  last_encoding_ = FrameEncoding::kProtobuf;
  if (raw_bytes > options_.compress_above_bytes) {
    raw_.resize(raw_bytes);
    message.SerializeWithCachedSizesToArray(reinterpret_cast<uint8_t*>(raw_.data()));
    uLongf bound = compressBound(raw_bytes);
    frame_.resize(kFrameHeaderBytes + 4 + bound);
    auto* out = reinterpret_cast<uint8_t*>(frame_.data());
    const int rc =
        compress2(out + kFrameHeaderBytes + 4, &bound, reinterpret_cast<const Bytef*>(raw_.data()),
                  raw_bytes, options_.zlib_level);
    // Incompressible bodies (rare: packed doubles of noise) go out raw.
    if (rc == Z_OK && bound + 4 < raw_bytes) {
      const size_t body = 4 + bound;
      PutLe32(out, static_cast<uint32_t>(body));
      out[4] = static_cast<uint8_t>(FrameEncoding::kZlib);
      out[5] = out[6] = out[7] = 0;
      PutLe32(out + kFrameHeaderBytes, static_cast<uint32_t>(raw_bytes));
      frame_.resize(kFrameHeaderBytes + body);
      last_encoding_ = FrameEncoding::kZlib;
      return frame_;
    }
  }
  frame_.resize(kFrameHeaderBytes + raw_bytes);
  auto* out = reinterpret_cast<uint8_t*>(frame_.data());
  PutLe32(out, static_cast<uint32_t>(raw_bytes));
  out[4] = static_cast<uint8_t>(FrameEncoding::kProtobuf);
  out[5] = out[6] = out[7] = 0;
  message.SerializeWithCachedSizesToArray(out + kFrameHeaderBytes);
  return frame_;
}

size_t ParseFrameHeader(const uint8_t* header, size_t max_frame_bytes, FrameEncoding* encoding) {
  const size_t body = GetLe32(header);
  if (header[5] != 0 || header[6] != 0 || header[7] != 0) {
    throw Error("bad frame: reserved header bytes are not zero (stream out of sync?)");
  }
  if (header[4] > static_cast<uint8_t>(FrameEncoding::kZlib)) {
    throw Error("bad frame: unknown encoding " + std::to_string(header[4]));
  }
  if (body > max_frame_bytes) throw Error(TooLong("body", body, max_frame_bytes));
  *encoding = static_cast<FrameEncoding>(header[4]);
  return body;
}

void DecodeFrameBody(FrameEncoding encoding, std::string_view body, size_t max_frame_bytes,
                     std::string* scratch, proto::coord::CoordinatorMessage* message) {
  std::string_view raw = body;
  if (encoding == FrameEncoding::kZlib) {
    if (body.size() < 4) throw Error("bad frame: zlib body shorter than its length field");
    const size_t declared = GetLe32(reinterpret_cast<const uint8_t*>(body.data()));
    if (declared > max_frame_bytes) {
      throw Error(TooLong("decompressed body", declared, max_frame_bytes));
    }
    scratch->resize(declared);
    uLongf inflated = declared;
    const int rc = uncompress(reinterpret_cast<Bytef*>(scratch->data()), &inflated,
                              reinterpret_cast<const Bytef*>(body.data() + 4), body.size() - 4);
    if (rc != Z_OK) {
      throw Error(std::string("bad frame: zlib: ") + (rc == Z_BUF_ERROR    ? "longer than declared"
                                                      : rc == Z_DATA_ERROR ? "corrupt stream"
                                                                           : zError(rc)));
    }
    if (inflated != declared) {
      throw Error("bad frame: zlib body inflated to " + std::to_string(inflated) +
                  " bytes, header declared " + std::to_string(declared));
    }
    raw = *scratch;
  }
  if (!message->ParseFromArray(raw.data(), static_cast<int>(raw.size()))) {
    throw Error("bad frame: " + std::to_string(raw.size()) +
                " bytes are not a valid CoordinatorMessage");
  }
}

}  // namespace sitlnet::coordinator

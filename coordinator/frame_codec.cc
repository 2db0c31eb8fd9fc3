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

// deflate/inflate streams initialized on first use and reset per frame.
struct ZlibStreams {
  z_stream stream{};
  bool deflating = false;
  bool inflating = false;
  ~ZlibStreams() {
    if (deflating) deflateEnd(&stream);
    if (inflating) inflateEnd(&stream);
  }
};

FrameEncoder::FrameEncoder(FrameCodecOptions options) : options_(options) {}
FrameEncoder::~FrameEncoder() = default;
FrameEncoder::FrameEncoder(FrameEncoder&&) noexcept = default;
FrameEncoder& FrameEncoder::operator=(FrameEncoder&&) noexcept = default;
FrameScratch::FrameScratch() = default;
FrameScratch::~FrameScratch() = default;
FrameScratch::FrameScratch(FrameScratch&&) noexcept = default;
FrameScratch& FrameScratch::operator=(FrameScratch&&) noexcept = default;

namespace {

// One-shot deflate of `in` into `out` (capacity *out_bytes) with a reused
// stream. Returns false if it did not fit or zlib failed.
bool Deflate(ZlibStreams* z, int level, const uint8_t* in, size_t in_bytes, uint8_t* out,
             size_t* out_bytes) {
  if (!z->deflating) {
    if (deflateInit(&z->stream, level) != Z_OK) return false;
    z->deflating = true;
  } else if (deflateReset(&z->stream) != Z_OK) {
    return false;
  }
  z->stream.next_in = const_cast<uint8_t*>(in);
  z->stream.avail_in = static_cast<uInt>(in_bytes);
  z->stream.next_out = out;
  z->stream.avail_out = static_cast<uInt>(*out_bytes);
  if (deflate(&z->stream, Z_FINISH) != Z_STREAM_END) return false;
  *out_bytes = z->stream.total_out;
  return true;
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
    if (!zlib_) zlib_ = std::make_unique<ZlibStreams>();
    // Only a result smaller than the raw body is worth sending: stop there.
    size_t bound = raw_bytes;
    frame_.resize(kFrameHeaderBytes + 4 + bound);
    auto* out = reinterpret_cast<uint8_t*>(frame_.data());
    const bool ok =
        Deflate(zlib_.get(), options_.zlib_level, reinterpret_cast<const uint8_t*>(raw_.data()),
                raw_bytes, out + kFrameHeaderBytes + 4, &bound);
    // Incompressible bodies (packed doubles of noise) go out raw.
    if (ok && bound + 4 < raw_bytes) {
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
                     FrameScratch* scratch, proto::coord::CoordinatorMessage* message) {
  std::string_view raw = body;
  if (encoding == FrameEncoding::kZlib) {
    if (body.size() < 4) throw Error("bad frame: zlib body shorter than its length field");
    const size_t declared = GetLe32(reinterpret_cast<const uint8_t*>(body.data()));
    if (declared > max_frame_bytes) {
      throw Error(TooLong("decompressed body", declared, max_frame_bytes));
    }
    std::string& inflated_body = scratch->inflated_;
    inflated_body.resize(declared);
    if (!scratch->zlib_) scratch->zlib_ = std::make_unique<ZlibStreams>();
    ZlibStreams& z = *scratch->zlib_;
    int rc = Z_OK;
    if (!z.inflating) {
      rc = inflateInit(&z.stream);
      z.inflating = rc == Z_OK;
    } else {
      rc = inflateReset(&z.stream);
    }
    if (rc != Z_OK) throw Error(std::string("zlib inflate set-up: ") + zError(rc));
    z.stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(body.data() + 4));
    z.stream.avail_in = static_cast<uInt>(body.size() - 4);
    z.stream.next_out = reinterpret_cast<Bytef*>(inflated_body.data());
    z.stream.avail_out = static_cast<uInt>(declared);
    rc = inflate(&z.stream, Z_FINISH);
    const size_t inflated = z.stream.total_out;
    if (rc != Z_STREAM_END) {
      // Z_BUF_ERROR with the output full: the stream holds more than declared.
      throw Error(std::string("bad frame: zlib: ") + (rc == Z_BUF_ERROR && inflated == declared
                                                          ? "longer than declared"
                                                      : rc == Z_BUF_ERROR  ? "truncated stream"
                                                      : rc == Z_DATA_ERROR ? "corrupt stream"
                                                                           : zError(rc)));
    }
    if (inflated != declared) {
      throw Error("bad frame: zlib body inflated to " + std::to_string(inflated) +
                  " bytes, header declared " + std::to_string(declared));
    }
    raw = inflated_body;
  }
  if (!message->ParseFromArray(raw.data(), static_cast<int>(raw.size()))) {
    throw Error("bad frame: " + std::to_string(raw.size()) +
                " bytes are not a valid CoordinatorMessage");
  }
}

}  // namespace sitlnet::coordinator

// Framing of coordinator messages: a fixed 8-byte header, then the body.
//
//   bytes 0..3  body length, little-endian uint32 (header excluded)
//   byte  4     encoding: 0 = protobuf, 1 = zlib-compressed protobuf
//   bytes 5..7  zero (reserved; non-zero means the stream lost sync)
//   body        encoding 0: the serialized CoordinatorMessage
//               encoding 1: uncompressed length (LE uint32), then a zlib stream
//
// Compression is chosen per frame by the sender (above a size threshold, and
// only if it actually shrinks the body), so receivers accept both encodings.
#ifndef SITLNET_COORDINATOR_FRAME_CODEC_H_
#define SITLNET_COORDINATOR_FRAME_CODEC_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "sitlnet/coordinator.pb.h"

namespace sitlnet::coordinator {

inline constexpr size_t kFrameHeaderBytes = 8;
// Default bound on a body (and on a decompressed body): 64 MiB is ~1.4 M robot
// poses, far above any scenario, and small enough that a corrupt length
// cannot make us allocate gigabytes.
inline constexpr size_t kDefaultMaxFrameBytes = size_t{64} << 20;
// Never compress: the default on Unix sockets and TCP loopback, where zlib
// costs more than the copy it saves (docs/performance.md, "coordinator").
inline constexpr size_t kNeverCompress = SIZE_MAX;

enum class FrameEncoding : uint8_t { kProtobuf = 0, kZlib = 1 };

struct FrameCodecOptions {
  // Bodies strictly larger than this (serialized bytes) are zlib-compressed.
  size_t compress_above_bytes = kNeverCompress;
  int zlib_level = 1;  // Z_BEST_SPEED: the payloads are doubles, higher levels gain little.
  size_t max_frame_bytes = kDefaultMaxFrameBytes;
};

struct ZlibStreams;  // Reused deflate/inflate state (frame_codec.cc).

// Encodes messages into frames, reusing its buffers and its deflate state
// between calls (a fresh zlib stream costs ~50 µs of set-up, measured: more
// than compressing a 64-robot message).
class FrameEncoder {
 public:
  explicit FrameEncoder(FrameCodecOptions options = {});
  ~FrameEncoder();
  FrameEncoder(FrameEncoder&&) noexcept;
  FrameEncoder& operator=(FrameEncoder&&) noexcept;
  // Returns header + body; valid until the next call. Throws Error if the
  // message exceeds max_frame_bytes.
  std::string_view Encode(const proto::coord::CoordinatorMessage& message);
  // Encoding chosen by the last Encode().
  FrameEncoding last_encoding() const { return last_encoding_; }
  const FrameCodecOptions& options() const { return options_; }

 private:
  FrameCodecOptions options_;
  std::string raw_;
  std::string frame_;
  FrameEncoding last_encoding_ = FrameEncoding::kProtobuf;
  std::unique_ptr<ZlibStreams> zlib_;
};

// Decoder state reused between frames: the inflated body and the inflate stream.
class FrameScratch {
 public:
  FrameScratch();
  ~FrameScratch();
  FrameScratch(FrameScratch&&) noexcept;
  FrameScratch& operator=(FrameScratch&&) noexcept;

 private:
  friend void DecodeFrameBody(FrameEncoding, std::string_view, size_t, FrameScratch*,
                              proto::coord::CoordinatorMessage*);
  std::string inflated_;
  std::unique_ptr<ZlibStreams> zlib_;
};

// Parses a header; returns the body length. Throws Error ("bad frame: ...")
// if the length exceeds `max_frame_bytes`, the encoding is unknown or the
// reserved bytes are not zero.
size_t ParseFrameHeader(const uint8_t* header, size_t max_frame_bytes, FrameEncoding* encoding);

// Decodes a body into `message`. Throws Error ("bad frame: ...") on a bad
// zlib stream, a length mismatch, or bytes that are not a CoordinatorMessage.
// `scratch` is reused between calls.
void DecodeFrameBody(FrameEncoding encoding, std::string_view body, size_t max_frame_bytes,
                     FrameScratch* scratch, proto::coord::CoordinatorMessage* message);

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_FRAME_CODEC_H_

// Coordinator frames as a peer sends them: 8-byte header, then the body (protobuf or zlib).
// Inputs are header + body; a bound of 1 MiB keeps a corrupt length from exhausting memory
// (the production bound, 64 MiB, is checked the same way).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/common.h"
#include "coordinator/frame_codec.h"

namespace coord = sitlnet::coordinator;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr size_t kMaxFrameBytes = size_t{1} << 20;
  if (size < coord::kFrameHeaderBytes) return 0;
  static coord::FrameScratch scratch;  // Reused between frames, as a connection does.
  try {
    coord::FrameEncoding encoding;
    const size_t length = coord::ParseFrameHeader(data, kMaxFrameBytes, &encoding);
    if (length > kMaxFrameBytes) __builtin_trap();
    // The body is what follows the header, whatever length the header claims (a short read
    // would block in production; a longer one is the next frame).
    const std::string_view body(reinterpret_cast<const char*>(data) + coord::kFrameHeaderBytes,
                                std::min(length, size - coord::kFrameHeaderBytes));
    sitlnet::proto::coord::CoordinatorMessage message;
    coord::DecodeFrameBody(encoding, body, kMaxFrameBytes, &scratch, &message);
    // What decodes must re-encode.
    coord::FrameEncoder encoder;
    encoder.Encode(message);
  } catch (const sitlnet::Error&) {
  }
  return 0;
}

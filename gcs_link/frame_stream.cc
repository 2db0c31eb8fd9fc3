#include "gcs_link/frame_stream.h"

#include "common/common.h"
#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

// The longest frame: a signed MAVLink 2 frame with a full payload.
constexpr size_t kMaxFrameBytes = mavlink::kHeaderV2Bytes + mavlink::kMaxPayloadBytes +
                                  mavlink::kChecksumBytes + mavlink::kSignatureBytes;

bool IsMagic(uint8_t byte) { return byte == mavlink::kMagicV1 || byte == mavlink::kMagicV2; }

}  // namespace

size_t ForEachFrame(const uint8_t* data, size_t size,
                    const std::function<void(const uint8_t* frame, size_t bytes)>& frame) {
  size_t at = 0, skipped = 0;
  while (at < size) {
    const size_t frame_bytes = mavlink::FrameBytes(data + at, size - at);
    if (frame_bytes == 0) {
      ++skipped;
      ++at;
      continue;
    }
    frame(data + at, frame_bytes);
    at += frame_bytes;
  }
  return skipped;
}

size_t FrameStream::Push(const uint8_t* data, size_t size, std::vector<uint8_t>* frames) {
  pending_.insert(pending_.end(), data, data + size);
  size_t at = 0, taken = 0;
  while (at < pending_.size()) {
    if (!IsMagic(pending_[at])) {
      ++bytes_dropped_;
      ++at;
      continue;
    }
    const size_t frame_bytes = mavlink::FrameBytes(pending_.data() + at, pending_.size() - at);
    if (frame_bytes == 0) break;  // Incomplete: wait for more (a stream) or DropRest().
    frames->insert(frames->end(), pending_.begin() + static_cast<long>(at),
                   pending_.begin() + static_cast<long>(at + frame_bytes));
    at += frame_bytes;
    ++taken;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(at));
  SITLNET_DEMAND(pending_.size() <= kMaxFrameBytes);
  return taken;
}

void FrameStream::DropRest() {
  bytes_dropped_ += pending_.size();
  pending_.clear();
}

}  // namespace sitlnet::gcs

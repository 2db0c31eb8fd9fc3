// What a GCS sends, cut into whole MAVLink 1 or 2 frames (mavlink::FrameBytes, by header) before
// it goes on the radio: bytes that begin no frame are dropped and counted, so junk from the host
// costs the simulated radio nothing. A TCP client's bytes are a stream (a frame may span reads);
// a UDP datagram ends whatever it began.
#ifndef SITLNET_GCS_LINK_FRAME_STREAM_H_
#define SITLNET_GCS_LINK_FRAME_STREAM_H_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace sitlnet::gcs {

// Calls `frame` with each whole MAVLink 1 or 2 frame of `data` (a datagram) in order; returns
// the bytes that began no frame, a frame cut short included.
size_t ForEachFrame(const uint8_t* data, size_t size,
                    const std::function<void(const uint8_t* frame, size_t bytes)>& frame);

class FrameStream {
 public:
  // Appends `size` bytes and moves every whole frame now complete to the end of `frames`;
  // returns how many. Bytes before a magic byte are dropped (counted in bytes_dropped()).
  size_t Push(const uint8_t* data, size_t size, std::vector<uint8_t>* frames);
  // Drops the start of a frame still incomplete (a datagram's end), counting its bytes.
  void DropRest();
  uint64_t bytes_dropped() const { return bytes_dropped_; }

 private:
  std::vector<uint8_t> pending_;
  uint64_t bytes_dropped_ = 0;
};

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_FRAME_STREAM_H_

// gcs.tlog: the MAVLink a ground station relayed, in the telemetry log format QGroundControl and
// MAVProxy write and replay: before each frame, its time as a big-endian unsigned 64-bit count of
// microseconds. Here the time is the simulation's (virtual time since the run's start), not the
// host's clock, so a lockstep run's log is as reproducible as the frames it holds.
#ifndef SITLNET_GCS_LINK_TLOG_WRITER_H_
#define SITLNET_GCS_LINK_TLOG_WRITER_H_

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "gcs_link/gcs_link.h"

namespace sitlnet::gcs {

class TlogWriter {
 public:
  // Creates (truncates) `path`. Throws Error naming it.
  explicit TlogWriter(const std::string& path);
  ~TlogWriter();
  TlogWriter(const TlogWriter&) = delete;
  TlogWriter& operator=(const TlogWriter&) = delete;

  // Writes each whole MAVLink 1 or 2 frame of `datagram` after the stamp `virtual_ns` (rounded
  // down to a microsecond); bytes that begin no frame, and a frame cut short, are counted in
  // tlog_bytes_skipped, frames in tlog_frames.
  void AppendDatagram(TimeNs virtual_ns, const uint8_t* datagram, size_t size,
                      GcsRelayCounters* counters);
  // Flushes and closes; throws Error naming the file if a write failed. Idempotent.
  void Close();

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_TLOG_WRITER_H_

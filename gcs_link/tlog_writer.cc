#include "gcs_link/tlog_writer.h"

#include <cerrno>

#include "gcs_link/frame_stream.h"

namespace sitlnet::gcs {

TlogWriter::TlogWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wbe");
  if (file_ == nullptr) throw Error(SystemErrorMessage("create " + path, errno));
}

TlogWriter::~TlogWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void TlogWriter::AppendDatagram(TimeNs virtual_ns, const uint8_t* datagram, size_t size,
                                GcsRelayCounters* counters) {
  const uint64_t stamp_us = static_cast<uint64_t>(virtual_ns < 0 ? 0 : virtual_ns / kNsPerUs);
  uint8_t stamp[8];
  for (int i = 0; i < 8; ++i) stamp[i] = static_cast<uint8_t>(stamp_us >> (56 - 8 * i));
  counters->tlog_bytes_skipped +=
      ForEachFrame(datagram, size, [&](const uint8_t* frame, size_t bytes) {
        std::fwrite(stamp, 1, sizeof stamp, file_);
        std::fwrite(frame, 1, bytes, file_);
        ++counters->tlog_frames;
      });
}

void TlogWriter::Close() {
  if (file_ == nullptr) return;
  const bool failed = std::ferror(file_) != 0;
  const bool close_failed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed || close_failed) throw Error("write " + path_ + ": the telemetry log is incomplete");
}

}  // namespace sitlnet::gcs

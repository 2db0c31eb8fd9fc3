#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

#include "common/common.h"

namespace sitlnet {

LineFile::LineFile(const std::string& path, const std::string& header, int lines_per_flush,
                   std::string_view what)
    : path_(path), what_(what), lines_per_flush_(lines_per_flush < 1 ? 1 : lines_per_flush) {
  fd_ = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) throw Error(SystemErrorMessage("create " + what_ + " \"" + path + "\"", errno));
  if (!header.empty()) {
    buffer_ = header + "\n";
    Flush();
  }
}

LineFile::~LineFile() {
  try {
    Flush();
  } catch (const Error& error) {
    std::fprintf(stderr, "sitlnet: %s\n", error.what());
  }
  if (fd_ >= 0) close(fd_);
}

void LineFile::Append(std::string_view line) {
  buffer_.append(line);
  buffer_ += '\n';
  if (++pending_ >= lines_per_flush_) Flush();
}

void LineFile::AppendRecord(std::string_view bytes) {
  buffer_.append(bytes);
  if (++pending_ >= lines_per_flush_) Flush();
}

void LineFile::Flush() {
  size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      buffer_.erase(0, done);
      throw Error(SystemErrorMessage("write " + what_ + " \"" + path_ + "\"", errno));
    }
    done += static_cast<size_t>(n);
  }
  buffer_.clear();
  pending_ = 0;
}

}  // namespace sitlnet

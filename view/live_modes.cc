#include "view/live_modes.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

namespace sitlnet::view {

LiveModes::LiveModes(const std::string& run_dir, int robots)
    : path_(run_dir + "/medium.pcap"), robots_(robots), reader_(robots) {}

LiveModes::~LiveModes() = default;

void LiveModes::Update() {
  if (failed_) return;
  if (!fd_.valid()) fd_.Reset(open(path_.c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd_.valid()) return;  // Not created yet (or a run without one): no modes.
  uint8_t buffer[1 << 16];
  try {
    for (;;) {
      const ssize_t n = read(fd_.get(), buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;
      reader_.Push(buffer, static_cast<size_t>(n));
    }
  } catch (const Error& error) {
    failed_ = true;
    std::fprintf(stderr, "sitlnet run: live view: \"%s\": %s; no autopilot modes shown\n",
                 path_.c_str(), error.what());
  }
}

std::vector<ModeChange> LiveModes::Latest() const {
  std::vector<ModeChange> latest;
  for (int robot = 0; robot < robots_; ++robot) {
    if (const ModeChange* change = reader_.Latest(robot)) latest.push_back(*change);
  }
  return latest;
}

}  // namespace sitlnet::view

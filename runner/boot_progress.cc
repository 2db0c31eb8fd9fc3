#include "runner/boot_progress.h"

#include <algorithm>

namespace sitlnet::runner {

BootProgress::BootProgress(int robots, int cores, TimeNs start_ns)
    : robots_(static_cast<size_t>(robots)), cores_(std::max(1, cores)) {
  for (Robot& robot : robots_) robot.progressed_ns = start_ns;
}

void BootProgress::Observe(int robot, const BootSample& sample, int booting, TimeNs now_ns) {
  Robot& r = robots_[static_cast<size_t>(robot)];
  if (!r.seen) {  // The first sample is the baseline: what the robot did before is unknown.
    r.seen = true;
    r.at_progress = sample;
    return;
  }
  const double fair_share = std::min(1.0, static_cast<double>(cores_) / std::max(1, booting));
  const TimeNs wall_ns = now_ns - r.progressed_ns;
  const bool logged = sample.log_bytes > r.at_progress.log_bytes;
  const bool computed = sample.cpu_ns >= 0 && r.at_progress.cpu_ns >= 0 && wall_ns > 0 &&
                        static_cast<double>(sample.cpu_ns - r.at_progress.cpu_ns) >=
                            0.5 * fair_share * static_cast<double>(wall_ns);
  if (logged || computed) {
    r.at_progress = sample;
    r.progressed_ns = now_ns;
  }
}

TimeNs BootProgress::StillForNs(int robot, TimeNs now_ns) const {
  return now_ns - robots_[static_cast<size_t>(robot)].progressed_ns;
}

}  // namespace sitlnet::runner

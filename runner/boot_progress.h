// Whether each booting robot is getting anywhere, so that the wait for the robots to speak to
// physics (robot_start.h) follows what the fleet is doing: 16 PX4 booting on 2 cores take longer
// than one, but each keeps logging and using CPU; a hung robot does neither and is named once it
// has been still for the stall window (issue 46, item 5; docs/run.md, "Readiness and restarts").
#ifndef SITLNET_RUNNER_BOOT_PROGRESS_H_
#define SITLNET_RUNNER_BOOT_PROGRESS_H_

#include <cstdint>
#include <vector>

#include "common/common.h"

namespace sitlnet::runner {

// A booting robot whose log and CPU time stay still this long is named (robot_start.h).
inline constexpr TimeNs kBootStallNs = 10 * kNsPerS;

// What is seen of one robot at one moment.
struct BootSample {
  int64_t log_bytes = 0;
  TimeNs cpu_ns = -1;  // CPU time of every process of the robot; -1: not accounted (no cgroup).
};

class BootProgress {
 public:
  // `cores`: the CPUs the robots share.
  BootProgress(int robots, int cores, TimeNs start_ns);

  // Records robot `robot`'s sample at `now_ns`, while `booting` robots (it included) have not
  // spoken yet. Progress: its log grew, or since its last progress it used at least half of its
  // fair share of the CPU (cores / booting, at most one core). Half a share, because a robot
  // that waits rather than boots still uses some: PX4 waiting for a simulator that never
  // answers uses 15 % of a core, which a lone robot's threshold (50 %) does not count.
  void Observe(int robot, const BootSample& sample, int booting, TimeNs now_ns);
  // Wall time since robot `robot` last progressed (since the start, before any).
  TimeNs StillForNs(int robot, TimeNs now_ns) const;

 private:
  struct Robot {
    BootSample at_progress;  // The sample when it last progressed.
    bool seen = false;
    TimeNs progressed_ns = 0;
  };
  std::vector<Robot> robots_;
  int cores_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_BOOT_PROGRESS_H_

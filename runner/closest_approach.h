// The closest two robots came during a run (summary.json "separation"): the smallest distance
// between any two robots' positions at the instants trajectories.csv samples. A swept
// experiment's collision margin (docs/sweep-reference.md, "Metrics").
#ifndef SITLNET_RUNNER_CLOSEST_APPROACH_H_
#define SITLNET_RUNNER_CLOSEST_APPROACH_H_

#include <optional>
#include <vector>

#include "common/common.h"

namespace sitlnet::runner {

struct ClosestApproach {
  double distance_m = 0;  // 3D, between the robots' body origins.
  TimeNs time_ns = 0;     // The first sample at which it was reached.
  int robot_a = 0;        // Global robot indices, robot_a < robot_b.
  int robot_b = 0;
};

class ClosestApproachTracker {
 public:
  // `positions_m`: x, y, z of every robot of the run, in global index order, at `time_ns`.
  // Samples come in time order; a tie keeps the earlier sample and then the lower pair.
  void Sample(TimeNs time_ns, const std::vector<double>& positions_m);
  // Null before a sample with two robots or more.
  const std::optional<ClosestApproach>& closest() const { return closest_; }

 private:
  std::optional<ClosestApproach> closest_;
  double closest_m2_ = 0;  // Its squared distance, compared as found (no rounding through sqrt).
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_CLOSEST_APPROACH_H_

// The iterations' timing per simulated second (metrics.csv's stf and lag_ns): what the view's
// timeline draws, live and replayed, from the same arithmetic.
#ifndef SITLNET_RUNNER_SECOND_TIMING_H_
#define SITLNET_RUNNER_SECOND_TIMING_H_

#include <cstdint>
#include <optional>

#include "common/common.h"

namespace sitlnet::runner {

// The iterations that start in second `second` (start_ns / 1 s).
struct SecondTiming {
  int64_t second = 0;
  int64_t iterations = 0;
  double stf_mean = 0, stf_max = 0;
  TimeNs lag_max_ns = 0;
};

// Sums iterations, in start order, into seconds. A few additions per iteration, no allocation.
class SecondTimingAccumulator {
 public:
  // Adds one iteration. Returns the previous second once this iteration starts a later one.
  std::optional<SecondTiming> Add(TimeNs start_ns, double stf, TimeNs lag_ns);
  // The last second, if it has an iteration; then starts afresh.
  std::optional<SecondTiming> Finish();

 private:
  SecondTiming current_;
  double stf_sum_ = 0;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_SECOND_TIMING_H_

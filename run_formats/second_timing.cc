#include "run_formats/run_formats.h"

#include <algorithm>

namespace sitlnet::run_formats {

std::optional<SecondTiming> SecondTimingAccumulator::Add(TimeNs start_ns, double stf,
                                                         TimeNs lag_ns) {
  const int64_t second = start_ns / kNsPerS;
  std::optional<SecondTiming> done;
  if (current_.iterations > 0 && second != current_.second) done = Finish();
  if (current_.iterations == 0) current_.second = second;
  ++current_.iterations;
  stf_sum_ += stf;
  current_.stf_max = std::max(current_.stf_max, stf);
  current_.lag_max_ns = std::max(current_.lag_max_ns, lag_ns);
  return done;
}

std::optional<SecondTiming> SecondTimingAccumulator::Finish() {
  if (current_.iterations == 0) return std::nullopt;
  SecondTiming done = current_;
  done.stf_mean = stf_sum_ / static_cast<double>(done.iterations);
  current_ = {};
  stf_sum_ = 0;
  return done;
}

}  // namespace sitlnet::run_formats

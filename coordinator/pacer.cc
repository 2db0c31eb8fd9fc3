#include "coordinator/pacer.h"

namespace sitlnet::coordinator {

Pacer::Pacer(Pacing pacing, double realtime_factor, TimeNs iteration_ns)
    : pacing_(pacing), timebase_(realtime_factor), iteration_ns_(iteration_ns) {
  SITLNET_DEMAND(iteration_ns > 0);
}

TimeNs Pacer::DeadlineNs(int64_t iteration) const {
  if (pacing_ == Pacing::kLockstep) return timebase_.wall_origin_ns();
  // Computed from the virtual end time each time (not accumulated) so that
  // rounding never drifts.
  return timebase_.WallOf((iteration + 1) * iteration_ns_);
}

Pacer::Decision Pacer::AfterIteration(int64_t iteration, TimeNs now_ns) const {
  Decision decision;
  if (pacing_ == Pacing::kLockstep) {
    decision.sleep_until_ns = now_ns;
    return decision;
  }
  decision.sleep_until_ns = DeadlineNs(iteration);
  decision.lag_ns = timebase_.LagNs((iteration + 1) * iteration_ns_, now_ns);
  return decision;
}

bool LagWarner::ShouldWarn(TimeNs lag_ns, TimeNs now_ns) {
  if (lag_ns <= threshold_ns_) return false;
  if (last_warning_ns_ != INT64_MIN && now_ns - last_warning_ns_ < interval_ns_) return false;
  last_warning_ns_ = now_ns;
  return true;
}

}  // namespace sitlnet::coordinator

#include "coordinator/pacing.h"

#include <poll.h>

#include <cerrno>
#include <cmath>
#include <ctime>

namespace sitlnet::coordinator {

TimeNs SystemClock::NowNs() { return MonotonicNowNs(); }

void SystemClock::SleepUntilNs(TimeNs wall_ns) {
  timespec until{static_cast<time_t>(wall_ns / kNsPerS), static_cast<long>(wall_ns % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr) == EINTR) {
  }
}

bool SystemClock::SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) {
  if (interrupt_fd < 0) {
    SleepUntilNs(wall_ns);
    return true;
  }
  for (;;) {
    const TimeNs left_ns = wall_ns - NowNs();
    if (left_ns <= 0) return true;
    pollfd p{interrupt_fd, POLLIN, 0};
    const timespec timeout{static_cast<time_t>(left_ns / kNsPerS),
                           static_cast<long>(left_ns % kNsPerS)};
    if (ppoll(&p, 1, &timeout, nullptr) > 0 && (p.revents & POLLIN)) return false;
  }
}

Clock& DefaultClock() {
  static SystemClock clock;
  return clock;
}

std::string PacingName(Pacing pacing) {
  return pacing == Pacing::kRealtime ? "realtime" : "lockstep";
}

Pacer::Pacer(Pacing pacing, double realtime_factor, TimeNs iteration_ns)
    : pacing_(pacing), realtime_factor_(realtime_factor), iteration_ns_(iteration_ns) {
  if (!(realtime_factor > 0) || !std::isfinite(realtime_factor)) {
    throw Error("realtime_factor " + std::to_string(realtime_factor) + " must be > 0");
  }
  SITLNET_DEMAND(iteration_ns > 0);
}

TimeNs Pacer::DeadlineNs(int64_t iteration) const {
  if (pacing_ == Pacing::kLockstep) return wall_origin_ns_;
  // Computed from the virtual end time each time (not accumulated) so that
  // rounding never drifts: wall = origin + end_ns / factor.
  const TimeNs end_ns = (iteration + 1) * iteration_ns_;
  if (realtime_factor_ == 1.0) return wall_origin_ns_ + end_ns;
  return wall_origin_ns_ +
         static_cast<TimeNs>(std::llround(static_cast<double>(end_ns) / realtime_factor_));
}

Pacer::Decision Pacer::AfterIteration(int64_t iteration, TimeNs now_ns) const {
  Decision decision;
  if (pacing_ == Pacing::kLockstep) {
    decision.sleep_until_ns = now_ns;
    return decision;
  }
  const TimeNs deadline = DeadlineNs(iteration);
  decision.sleep_until_ns = deadline;
  decision.lag_ns = now_ns > deadline ? now_ns - deadline : 0;
  return decision;
}

bool LagWarner::ShouldWarn(TimeNs lag_ns, TimeNs now_ns) {
  if (lag_ns <= threshold_ns_) return false;
  if (last_warning_ns_ != INT64_MIN && now_ns - last_warning_ns_ < interval_ns_) return false;
  last_warning_ns_ = now_ns;
  return true;
}

}  // namespace sitlnet::coordinator

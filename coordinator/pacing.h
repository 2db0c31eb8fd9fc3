// Wall-clock pacing of iterations: `realtime` (virtual time follows the wall
// clock times a real-time factor) or `lockstep` (as fast as possible).
// The clock is injected so the deadline logic is testable without sleeping.
#ifndef SITLNET_COORDINATOR_PACING_H_
#define SITLNET_COORDINATOR_PACING_H_

#include <string>

#include "common/common.h"

namespace sitlnet::coordinator {

// A monotonic wall clock (nanoseconds, arbitrary origin).
class Clock {
 public:
  virtual ~Clock() = default;
  virtual TimeNs NowNs() = 0;
  // Returns once NowNs() >= wall_ns (at once if already past).
  virtual void SleepUntilNs(TimeNs wall_ns) = 0;
  // Same, but returns false early if `interrupt_fd` (>= 0) becomes readable.
  // Default: not interruptible.
  virtual bool SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) {
    SleepUntilNs(wall_ns);
    return true;
  }
};

// CLOCK_MONOTONIC; sleeps with clock_nanosleep(TIMER_ABSTIME) so deadlines
// do not drift with the time spent computing.
class SystemClock final : public Clock {
 public:
  TimeNs NowNs() override;
  void SleepUntilNs(TimeNs wall_ns) override;
  // ppoll() on the fd with the time left, re-armed until the deadline.
  bool SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) override;
};

// Process-wide instance of SystemClock.
Clock& DefaultClock();

enum class Pacing { kRealtime, kLockstep };
std::string PacingName(Pacing pacing);

// Deadlines of iterations. Iteration k covers virtual time [kΔ, (k+1)Δ); in
// realtime mode it must not end before wall_origin + (k+1)Δ / factor.
// Deadlines are absolute: an iteration that ran late does not shift later
// ones, so the run catches up when the host has spare time again.
class Pacer {
 public:
  Pacer(Pacing pacing, double realtime_factor, TimeNs iteration_ns);

  // Starts the wall clock of the run: iteration 0 begins at `wall_origin_ns`.
  void Begin(TimeNs wall_origin_ns) { wall_origin_ns_ = wall_origin_ns; }

  // Wall instant before which iteration k must not end (lockstep: the
  // origin, i.e. never wait).
  TimeNs DeadlineNs(int64_t iteration) const;

  struct Decision {
    TimeNs sleep_until_ns = 0;  // Sleep until here before the next START (<= now: do not).
    TimeNs lag_ns = 0;          // How late the iteration finished (0 if on time; lockstep 0).
  };
  // Called when every connector answered END of `iteration` at `now_ns`.
  Decision AfterIteration(int64_t iteration, TimeNs now_ns) const;

  Pacing pacing() const { return pacing_; }
  double realtime_factor() const { return realtime_factor_; }

 private:
  Pacing pacing_;
  double realtime_factor_;
  TimeNs iteration_ns_;
  TimeNs wall_origin_ns_ = 0;
};

// Decides when to warn that realtime pacing is falling behind: at most once
// per `interval_ns` of wall time, and only past `threshold_ns` of lag.
class LagWarner {
 public:
  LagWarner(TimeNs threshold_ns, TimeNs interval_ns)
      : threshold_ns_(threshold_ns), interval_ns_(interval_ns) {}
  bool ShouldWarn(TimeNs lag_ns, TimeNs now_ns);

 private:
  TimeNs threshold_ns_;
  TimeNs interval_ns_;
  TimeNs last_warning_ns_ = INT64_MIN;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_PACING_H_

// Wall-clock pacing of iterations: `realtime` (virtual time follows the wall
// clock times a real-time factor) or `lockstep` (as fast as possible).
// Deadlines come from the run's clock::Timebase (clock/clock.h), the one owner
// of the virtual<->wall mapping.
#ifndef SITLNET_COORDINATOR_PACER_H_
#define SITLNET_COORDINATOR_PACER_H_

#include <string>

#include "clock/clock.h"
#include "clock/pacing.h"
#include "common/common.h"

namespace sitlnet::coordinator {

// The clock's pacing type, by its coordinator name (one type from the CLI to the Pacer).
using clock::Pacing;
using clock::PacingName;

// Deadlines of iterations. Iteration k covers virtual time [kΔ, (k+1)Δ); in
// realtime mode it must not end before the wall instant of (k+1)Δ.
// Deadlines are absolute: an iteration that ran late does not shift later
// ones, so the run catches up when the host has spare time again.
class Pacer {
 public:
  Pacer(Pacing pacing, double realtime_factor, TimeNs iteration_ns);

  // Starts the wall clock of the run: iteration 0 begins at `wall_origin_ns`.
  void Begin(TimeNs wall_origin_ns) { timebase_.Begin(wall_origin_ns); }

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
  double realtime_factor() const { return timebase_.realtime_factor(); }
  const clock::Timebase& timebase() const { return timebase_; }

 private:
  Pacing pacing_;
  clock::Timebase timebase_;
  TimeNs iteration_ns_;
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

#endif  // SITLNET_COORDINATOR_PACER_H_

// Synthetic simulators for tests and benchmarks: they do no physics or
// radio, only a busy loop of a set wall duration per step (spinning on
// CLOCK_MONOTONIC, so the work is measured, not estimated) and messages of
// the real shapes (poses of N robots). Results built on them are labelled
// "synthetic" wherever they are reported.
#ifndef SITLNET_COORDINATOR_SYNTHETIC_H_
#define SITLNET_COORDINATOR_SYNTHETIC_H_

#include <cstdint>
#include <string>
#include <vector>

#include "coordinator/connector.h"

namespace sitlnet::coordinator {

struct SyntheticOptions {
  int robots = 1;
  TimeNs step_ns = 10 * kNsPerMs;   // δ of this simulator; steps per iteration = Δ/δ.
  TimeNs work_per_step_ns = 0;      // Busy wall time per step (all robots together).
  bool commands_collected = false;  // Physics: report CommandsCollected (lockstep robots).
};

// Physics stand-in: robot i moves on a circle, poses are exact functions of
// virtual time (so two runs are comparable bit for bit).
class SyntheticPhysics final : public Simulator {
 public:
  explicit SyntheticPhysics(SyntheticOptions options) : options_(options) {}
  proto::coord::Poses InitialPoses() override;
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;
  // Poses at virtual time t (what every End reports at its end_ns).
  static void PosesAt(int robots, TimeNs t_ns, proto::coord::Poses* poses);

 private:
  SyntheticOptions options_;
};

// Network stand-in: checks it got one position per robot, records the
// virtual start times and the first robot's x it saw (for tests).
class SyntheticNetwork final : public Simulator {
 public:
  explicit SyntheticNetwork(SyntheticOptions options) : options_(options) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;
  const std::vector<TimeNs>& start_times_ns() const { return start_times_ns_; }
  const std::vector<double>& first_robot_x_m() const { return first_robot_x_m_; }

 private:
  SyntheticOptions options_;
  std::vector<TimeNs> start_times_ns_;
  std::vector<double> first_robot_x_m_;
};

// Spins until `work_ns` of wall time has passed.
void BusyWaitNs(TimeNs work_ns);

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_SYNTHETIC_H_

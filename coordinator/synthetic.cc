#include "coordinator/synthetic.h"

#include <cmath>

namespace sitlnet::coordinator {

void BusyWaitNs(TimeNs work_ns) {
  if (work_ns <= 0) return;
  const TimeNs until = MonotonicNowNs() + work_ns;
  while (MonotonicNowNs() < until) {
  }
}

void SyntheticPhysics::PosesAt(int robots, TimeNs t_ns, proto::coord::Poses* poses) {
  poses->Clear();
  const double t_s = static_cast<double>(t_ns) / kNsPerS;
  for (int i = 0; i < robots; ++i) {
    // Radius 10 m around (3i, 0, 10), one turn per 20 s, phase by index.
    const double angle = 2 * M_PI * t_s / 20 + i;
    poses->add_position_m(3.0 * i + 10 * std::cos(angle));
    poses->add_position_m(10 * std::sin(angle));
    poses->add_position_m(10);
    poses->add_orientation_wxyz(std::cos(angle / 2));
    poses->add_orientation_wxyz(0);
    poses->add_orientation_wxyz(0);
    poses->add_orientation_wxyz(std::sin(angle / 2));
  }
}

proto::coord::Poses SyntheticPhysics::InitialPoses() {
  proto::coord::Poses poses;
  PosesAt(options_.robots, 0, &poses);
  return poses;
}

void SyntheticPhysics::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                    IterationContext& context) {
  if (options_.commands_collected) context.CommandsCollected();
  const TimeNs steps = (start.end_ns() - start.start_ns()) / options_.step_ns;
  for (TimeNs s = 0; s < steps; ++s) BusyWaitNs(options_.work_per_step_ns);
  PosesAt(options_.robots, start.end_ns(), end->mutable_poses());
}

void SyntheticNetwork::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                    IterationContext& context) {
  if (start.poses().position_m_size() != 3 * options_.robots) {
    throw Error("synthetic network: START of iteration " + std::to_string(start.iteration()) +
                " carries " + std::to_string(start.poses().position_m_size() / 3) +
                " positions, expected " + std::to_string(options_.robots));
  }
  start_times_ns_.push_back(start.start_ns());
  if (options_.robots > 0) first_robot_x_m_.push_back(start.poses().position_m(0));
  const TimeNs steps = (start.end_ns() - start.start_ns()) / options_.step_ns;
  for (TimeNs s = 0; s < steps; ++s) BusyWaitNs(options_.work_per_step_ns);
}

}  // namespace sitlnet::coordinator

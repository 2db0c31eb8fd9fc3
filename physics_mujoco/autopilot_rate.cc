// AutopilotRate's arithmetic (physics_mujoco.h).
#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

double AnswersPerSecond(uint64_t answers, TimeNs wall_ns) {
  if (wall_ns <= 0) return 0;
  return static_cast<double>(answers) * kNsPerS / static_cast<double>(wall_ns);
}

double AutopilotRate::AchievedHz() const {
  // n answers span n - 1 intervals between the first and the last.
  if (answers < 2) return 0;
  return AnswersPerSecond(answers - 1, last_answer_wall_ns - first_answer_wall_ns);
}

double AutopilotRate::Ratio() const { return nominal_hz > 0 ? AchievedHz() / nominal_hz : 0; }

}  // namespace sitlnet::physics

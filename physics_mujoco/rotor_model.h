// Quad-X rotor and motor model: thrust kf*w^2 along body +z, yaw reaction -s*km*w^2 by spin
// direction s, first-order motor lag with separate up/down time constants, speed limits.
#ifndef SITLNET_PHYSICS_MUJOCO_ROTOR_MODEL_H_
#define SITLNET_PHYSICS_MUJOCO_ROTOR_MODEL_H_

#include <mujoco/mujoco.h>

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

// Rotor i sits at (x_m[i], y_m[i]) in the body frame (FLU) and spins counter-clockwise seen
// from above when ccw[i] (ArduPilot quad-X: motors 1, 2 CCW; 3, 4 CW).
struct RotorLayout {
  std::array<double, kRotors> x_m{};
  std::array<double, kRotors> y_m{};
  std::array<bool, kRotors> ccw{};
};

RotorLayout QuadXLayout(double arm_x_m, double arm_y_m);

class RotorModel {
 public:
  RotorModel(const proto::Airframe& airframe, TimeNs step_ns);

  // One step of the motor lag: w += (target - w) * (1 - exp(-dt / tau)), tau = up or down
  // time constant by the sign of (target - w). Exact for a target held over the step.
  void StepMotors(const RotorSpeeds& target_rad_s, RotorSpeeds* speeds_rad_s) const;

  // Force (N) and torque (N*m) of the rotors on the body, body frame, about the centre of mass.
  void BodyWrench(const RotorSpeeds& speeds_rad_s, double force_n[3], double torque_n_m[3]) const;

  double max_speed_rad_s() const { return max_speed_rad_s_; }
  const RotorLayout& layout() const { return layout_; }

 private:
  RotorLayout layout_;
  double kf_;
  double km_;
  double max_speed_rad_s_;
  double alpha_up_;    // 1 - exp(-dt / tau_up)
  double alpha_down_;  // 1 - exp(-dt / tau_down)
};

// Writes the rotors' wrench at `speeds` plus linear drag -c*v into xfrc_applied of `body`
// (world frame, force then torque, at the centre of mass), using the attitude in d->qpos[3..6]
// (a free joint's quaternion: current, unlike xquat after mj_step).
void ApplyRotorWrench(const RotorModel& rotors, const RotorSpeeds& speeds,
                      double linear_drag_n_s_per_m, int body, mjData* d);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_ROTOR_MODEL_H_

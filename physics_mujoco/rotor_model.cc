#include "physics_mujoco/rotor_model.h"

#include <algorithm>
#include <cmath>

namespace sitlnet::physics {

RotorLayout QuadXLayout(double arm_x_m, double arm_y_m) {
  // ArduPilot SIM_Frame.cpp quad_x_motors: motor 1 at 45 deg (front-right) CCW, 2 at -135
  // (rear-left) CCW, 3 at -45 (front-left) CW, 4 at 135 (rear-right) CW; angles clockwise
  // from the nose, so "right" is -y in FLU.
  RotorLayout layout;
  layout.x_m = {arm_x_m, -arm_x_m, arm_x_m, -arm_x_m};
  layout.y_m = {-arm_y_m, arm_y_m, arm_y_m, -arm_y_m};
  layout.ccw = {true, true, false, false};
  return layout;
}

RotorModel::RotorModel(const proto::Airframe& airframe, TimeNs step_ns)
    : layout_(QuadXLayout(airframe.arm_x_m(), airframe.arm_y_m())),
      kf_(airframe.thrust_coefficient()),
      km_(airframe.drag_coefficient()),
      max_speed_rad_s_(airframe.max_rotor_speed_rad_s()) {
  const double dt_s = static_cast<double>(step_ns) / kNsPerS;
  alpha_up_ = -std::expm1(-dt_s / airframe.motor_time_constant_up_s());
  alpha_down_ = -std::expm1(-dt_s / airframe.motor_time_constant_down_s());
}

void RotorModel::StepMotors(const RotorSpeeds& target_rad_s, RotorSpeeds* speeds_rad_s) const {
  for (int i = 0; i < kRotors; ++i) {
    const double target = std::clamp(target_rad_s[i], 0.0, max_speed_rad_s_);
    double& speed = (*speeds_rad_s)[i];
    speed += (target - speed) * (target > speed ? alpha_up_ : alpha_down_);
  }
}

void RotorModel::BodyWrench(const RotorSpeeds& speeds_rad_s, double force_n[3],
                            double torque_n_m[3]) const {
  force_n[0] = force_n[1] = force_n[2] = 0;
  torque_n_m[0] = torque_n_m[1] = torque_n_m[2] = 0;
  for (int i = 0; i < kRotors; ++i) {
    const double w2 = speeds_rad_s[i] * speeds_rad_s[i];
    const double thrust_n = kf_ * w2;
    force_n[2] += thrust_n;
    // r x (0, 0, T) = (y T, -x T, 0).
    torque_n_m[0] += layout_.y_m[i] * thrust_n;
    torque_n_m[1] -= layout_.x_m[i] * thrust_n;
    // Aerodynamic drag on a rotor spinning CCW (+z) pushes the body CW (-z), and vice versa.
    torque_n_m[2] += (layout_.ccw[i] ? -1.0 : 1.0) * km_ * w2;
  }
}

void ApplyRotorWrench(const RotorModel& rotors, const RotorSpeeds& speeds,
                      double linear_drag_n_s_per_m, int body, mjData* d) {
  double force_body[3], torque_body[3], rotation[9];
  rotors.BodyWrench(speeds, force_body, torque_body);
  mju_quat2Mat(rotation, d->qpos + 3);
  double* applied = d->xfrc_applied + 6 * body;
  mju_mulMatVec(applied, rotation, force_body, 3, 3);
  mju_mulMatVec(applied + 3, rotation, torque_body, 3, 3);
  if (linear_drag_n_s_per_m != 0) {
    for (int i = 0; i < 3; ++i) applied[i] -= linear_drag_n_s_per_m * d->qvel[i];
  }
}

}  // namespace sitlnet::physics

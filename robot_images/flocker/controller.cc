#include "robot_images/flocker/controller.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace sitlnet::flocker {
namespace {

constexpr double kGravity_m_s2 = 9.80665;

// Rotor positions (FLU) and spin (+1 CCW seen from above) in ArduPilot quad-X
// order: 1 front-right CCW, 2 rear-left CCW, 3 front-left CW, 4 rear-right CW.
struct Rotor {
  double x_sign, y_sign, ccw;
};
constexpr Rotor kQuadX[4] = {{+1, -1, +1}, {-1, +1, +1}, {+1, +1, -1}, {-1, -1, -1}};

Eigen::Vector3d Vee(const Eigen::Matrix3d& skew) { return {skew(2, 1), skew(0, 2), skew(1, 0)}; }

}  // namespace

RotorSpeeds MixQuadX(const AirframeParams& airframe, double thrust_n,
                     const Eigen::Vector3d& torque_n_m) {
  // Wrench rows: thrust, roll (sum y*f), pitch (sum -x*f), yaw (reaction of
  // rotor drag: a CCW rotor pushes the body CW, -km/kf * f).
  Eigen::Matrix4d allocation;
  const double yaw_per_thrust = airframe.drag_coefficient / airframe.thrust_coefficient;
  for (int i = 0; i < 4; ++i) {
    const Rotor& r = kQuadX[i];
    allocation(0, i) = 1;
    allocation(1, i) = r.y_sign * airframe.arm_y_m;
    allocation(2, i) = -r.x_sign * airframe.arm_x_m;
    allocation(3, i) = -r.ccw * yaw_per_thrust;
  }
  const Eigen::Vector4d wrench(thrust_n, torque_n_m.x(), torque_n_m.y(), torque_n_m.z());
  Eigen::Vector4d forces = allocation.inverse() * wrench;
  const double max_force =
      airframe.thrust_coefficient * airframe.max_rotor_speed_rad_s * airframe.max_rotor_speed_rad_s;
  RotorSpeeds speeds{};
  for (int i = 0; i < 4; ++i) {
    const double force = std::clamp(forces[i], 0.0, max_force);
    speeds[i] = std::sqrt(force / airframe.thrust_coefficient);
  }
  return speeds;
}

RotorSpeeds ComputeRotorSpeeds(const AirframeParams& airframe, const ControllerGains& gains,
                               const VehicleState& state, const Eigen::Vector2d& velocity_xy_m_s,
                               double altitude_m, double yaw_rad) {
  // Velocity loop -> desired acceleration (world), tilt-limited.
  const double vz = std::clamp(gains.altitude_gain_1_s * (altitude_m - state.position_m.z()),
                               -gains.max_vertical_speed_m_s, gains.max_vertical_speed_m_s);
  const Eigen::Vector3d velocity_target(velocity_xy_m_s.x(), velocity_xy_m_s.y(), vz);
  Eigen::Vector3d accel = gains.velocity_gain_1_s * (velocity_target - state.velocity_m_s);
  const double max_horizontal = kGravity_m_s2 * std::tan(gains.max_tilt_rad);
  const double horizontal = accel.head<2>().norm();
  if (horizontal > max_horizontal) accel.head<2>() *= max_horizontal / horizontal;
  accel.z() = std::max(accel.z(), -0.5 * kGravity_m_s2);  // never command free fall

  // Desired attitude: body z along the required force, nose towards yaw_rad.
  const Eigen::Vector3d force = airframe.mass_kg * (accel + Eigen::Vector3d(0, 0, kGravity_m_s2));
  const Eigen::Vector3d z_body = force.normalized();
  const Eigen::Vector3d heading(std::cos(yaw_rad), std::sin(yaw_rad), 0);
  const Eigen::Vector3d y_body = z_body.cross(heading).normalized();
  const Eigen::Vector3d x_body = y_body.cross(z_body);
  Eigen::Matrix3d desired;
  desired << x_body, y_body, z_body;
  const Eigen::Matrix3d current = state.orientation.normalized().toRotationMatrix();

  // Attitude error on SO(3) (Lee et al. 2010) -> body rate setpoint.
  const Eigen::Vector3d attitude_error =
      0.5 * Vee(desired.transpose() * current - current.transpose() * desired);
  Eigen::Vector3d rate_target = -gains.attitude_gain_1_s * attitude_error;
  rate_target.z() =
      std::clamp(rate_target.z(), -gains.yaw_rate_limit_rad_s, gains.yaw_rate_limit_rad_s);

  // Rate loop -> torque, with the gyroscopic term.
  const Eigen::Vector3d& omega = state.angular_velocity_rad_s;
  const Eigen::Vector3d inertia_omega = airframe.inertia_kg_m2.cwiseProduct(omega);
  const Eigen::Vector3d torque =
      airframe.inertia_kg_m2.cwiseProduct(gains.rate_gain_1_s * (rate_target - omega)) +
      omega.cross(inertia_omega);
  const double thrust = force.dot(current.col(2));  // what the current tilt can use
  return MixQuadX(airframe, std::max(thrust, 0.0), torque);
}

}  // namespace sitlnet::flocker

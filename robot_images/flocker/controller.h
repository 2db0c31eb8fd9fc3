// Cascaded multirotor controller of the flocker image: position -> velocity
// -> attitude -> body rates -> four rotor speeds (quad-X, ArduPilot motor
// order). Frames as in proto/sitlnet/robot.proto: world ENU, body FLU.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_CONTROLLER_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_CONTROLLER_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace sitlnet::flocker {

// What the controller needs to know of the airframe (same meaning and units
// as proto/sitlnet/scenario.proto's Airframe).
struct AirframeParams {
  double mass_kg = 1.325;
  double arm_x_m = 0.14;
  double arm_y_m = 0.18;
  Eigen::Vector3d inertia_kg_m2{0.04, 0.0335, 0.06};
  double thrust_coefficient = 3.16e-6;  // N / (rad/s)^2
  double drag_coefficient = 6.35e-8;    // N*m / (rad/s)^2
  double max_rotor_speed_rad_s = 2028;
};

struct ControllerGains {
  double velocity_gain_1_s = 2.0;  // acceleration per m/s of velocity error
  double altitude_gain_1_s = 1.0;  // vertical speed per m of altitude error
  double max_vertical_speed_m_s = 2.0;
  double max_tilt_rad = 0.5;
  double attitude_gain_1_s = 8.0;  // body rate per rad of attitude error
  double rate_gain_1_s = 20.0;     // angular acceleration per rad/s of rate error
  double yaw_rate_limit_rad_s = 1.5;
};

struct VehicleState {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();   // body -> world
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();  // body
};

using RotorSpeeds = std::array<double, 4>;

// Rotor speeds that produce collective thrust `thrust_n` along body +z and
// body torque `torque_n_m`, as far as speed limits allow (thrust first).
RotorSpeeds MixQuadX(const AirframeParams& airframe, double thrust_n,
                     const Eigen::Vector3d& torque_n_m);

// One control update: track horizontal velocity `velocity_xy_m_s`, altitude
// `altitude_m` and heading `yaw_rad`.
RotorSpeeds ComputeRotorSpeeds(const AirframeParams& airframe, const ControllerGains& gains,
                               const VehicleState& state, const Eigen::Vector2d& velocity_xy_m_s,
                               double altitude_m, double yaw_rad);

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_CONTROLLER_H_

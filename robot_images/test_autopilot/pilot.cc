#include "robot_images/test_autopilot/pilot.h"

#include <cmath>

namespace sitlnet::test_autopilot {
namespace {

double Yaw(const Eigen::Quaterniond& q) {
  return std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
}

}  // namespace

MotorOutputs Pilot::Fly(const flocker::VehicleState& state) {
  const flocker::AirframeParams airframe;  // scenario.proto's Airframe defaults
  const flocker::ControllerGains gains;
  if (!yaw_rad_) yaw_rad_ = Yaw(state.orientation);
  Eigen::Vector2d velocity_xy = Eigen::Vector2d::Zero();
  const bool at_altitude = state.position_m.z() > 0.8 * mission_.altitude_m;
  if (mission_.waypoint_m && at_altitude) {
    velocity_xy = 0.5 * (*mission_.waypoint_m - state.position_m.head<2>());
    if (velocity_xy.norm() > 2) velocity_xy *= 2 / velocity_xy.norm();
  }
  const auto speeds = flocker::ComputeRotorSpeeds(airframe, gains, state, velocity_xy,
                                                  mission_.altitude_m, *yaw_rad_);
  MotorOutputs motors;
  for (int i = 0; i < 4; ++i) motors[i] = speeds[i] / airframe.max_rotor_speed_rad_s;
  return motors;
}

}  // namespace sitlnet::test_autopilot

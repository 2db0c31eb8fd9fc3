#include "physics_mujoco/rotor_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sitlnet::physics {
namespace {

TEST(RotorModelTest, ThrustAndTorquesFollowTheQuadXLayout) {
  proto::Airframe airframe;  // defaults
  const RotorModel rotors(airframe, kNsPerMs);
  const double w = 1000;
  const double kf = airframe.thrust_coefficient();
  const double km = airframe.drag_coefficient();
  double force[3], torque[3];
  rotors.BodyWrench({w, w, w, w}, force, torque);
  EXPECT_DOUBLE_EQ(force[2], 4 * kf * w * w);
  EXPECT_NEAR(torque[0], 0, 1e-12);
  EXPECT_NEAR(torque[1], 0, 1e-12);
  EXPECT_NEAR(torque[2], 0, 1e-12);
  // Only motor 1 (front-right, CCW) lifts the right side (torque_x = y*T < 0 in FLU) and the
  // nose (torque_y = -x*T < 0) and yaws the body clockwise (drag of a CCW rotor: -z).
  rotors.BodyWrench({w, 0, 0, 0}, force, torque);
  const double thrust = kf * w * w;
  EXPECT_DOUBLE_EQ(torque[0], -airframe.arm_y_m() * thrust);
  EXPECT_DOUBLE_EQ(torque[1], -airframe.arm_x_m() * thrust);
  EXPECT_DOUBLE_EQ(torque[2], -km * w * w);
  // Motor 3 (front-left, CW) yaws counter-clockwise.
  rotors.BodyWrench({0, 0, w, 0}, force, torque);
  EXPECT_DOUBLE_EQ(torque[2], km * w * w);
}

TEST(RotorModelTest, MotorLagUsesUpAndDownTimeConstants) {
  proto::Airframe airframe;
  const TimeNs step_ns = 100 * kNsPerUs;
  const RotorModel rotors(airframe, step_ns);
  RotorSpeeds speeds{};
  const RotorSpeeds target{1000, 1000, 1000, 1000};
  // After one up time constant a first-order lag covers 1 - 1/e of the way.
  const int up_steps =
      static_cast<int>(std::lround(airframe.motor_time_constant_up_s() * kNsPerS / step_ns));
  for (int i = 0; i < up_steps; ++i) rotors.StepMotors(target, &speeds);
  EXPECT_NEAR(speeds[0], 1000 * (1 - std::exp(-1.0)), 1e-6);
  // Spinning down from 1000 toward 0 for one down time constant leaves 1/e.
  speeds = target;
  const int down_steps =
      static_cast<int>(std::lround(airframe.motor_time_constant_down_s() * kNsPerS / step_ns));
  for (int i = 0; i < down_steps; ++i) rotors.StepMotors({}, &speeds);
  EXPECT_NEAR(speeds[0], 1000 * std::exp(-1.0), 1e-6);
}

TEST(RotorModelTest, TargetsAreClampedToTheSpeedLimit) {
  proto::Airframe airframe;
  const RotorModel rotors(airframe, kNsPerMs);
  RotorSpeeds speeds{};
  const double max = airframe.max_rotor_speed_rad_s();
  for (int i = 0; i < 2000; ++i) rotors.StepMotors({1e9, 1e9, -5, 0}, &speeds);
  EXPECT_NEAR(speeds[0], max, 1e-9 * max);
  EXPECT_LE(speeds[0], max);
  EXPECT_EQ(speeds[2], 0);
}

}  // namespace
}  // namespace sitlnet::physics

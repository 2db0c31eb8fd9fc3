#include "robot_images/flocker/controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sitlnet::flocker {
namespace {

constexpr double kG = 9.80665;

// Independent forward model: force and torque of quad-X rotor speeds,
// written from the rotor layout in proto/sitlnet/robot.proto's comment.
void Wrench(const AirframeParams& a, const RotorSpeeds& w, double* thrust, Eigen::Vector3d* tau) {
  const double x[4] = {a.arm_x_m, -a.arm_x_m, a.arm_x_m, -a.arm_x_m};  // F, R, F, R
  const double y[4] = {-a.arm_y_m, a.arm_y_m, a.arm_y_m, -a.arm_y_m};  // R, L, L, R
  const double spin[4] = {+1, +1, -1, -1};                             // CCW, CCW, CW, CW
  *thrust = 0;
  tau->setZero();
  for (int i = 0; i < 4; ++i) {
    const double f = a.thrust_coefficient * w[i] * w[i];
    *thrust += f;
    (*tau) += Eigen::Vector3d(y[i] * f, -x[i] * f, -spin[i] * a.drag_coefficient * w[i] * w[i]);
  }
}

TEST(MixQuadXTest, ReproducesRequestedWrench) {
  AirframeParams airframe;
  const Eigen::Vector3d torque(0.05, -0.03, 0.01);
  const RotorSpeeds speeds = MixQuadX(airframe, 14.0, torque);
  double thrust;
  Eigen::Vector3d achieved;
  Wrench(airframe, speeds, &thrust, &achieved);
  EXPECT_NEAR(thrust, 14.0, 1e-9);
  EXPECT_NEAR((achieved - torque).norm(), 0, 1e-9);
}

TEST(ControllerTest, LevelAtTargetGivesHoverSpeedOnEveryRotor) {
  AirframeParams airframe;
  VehicleState state;
  state.position_m = {0, 0, 5};
  const RotorSpeeds speeds =
      ComputeRotorSpeeds(airframe, ControllerGains{}, state, {0, 0}, 5.0, 0.0);
  const double hover = std::sqrt(airframe.mass_kg * kG / (4 * airframe.thrust_coefficient));
  for (double w : speeds) EXPECT_NEAR(w, hover, 1e-6 * hover);
}

TEST(ControllerTest, WantingToGoEastPitchesTheNoseDown) {
  AirframeParams airframe;
  VehicleState state;
  state.position_m = {0, 0, 5};
  const RotorSpeeds speeds =
      ComputeRotorSpeeds(airframe, ControllerGains{}, state, {2, 0}, 5.0, 0.0);
  double thrust;
  Eigen::Vector3d torque;
  Wrench(airframe, speeds, &thrust, &torque);
  // Facing east (+x), accelerating east needs a positive pitch rate about +y (FLU): nose down.
  EXPECT_GT(torque.y(), 0);
  EXPECT_NEAR(torque.x(), 0, 1e-9);
}

TEST(ControllerTest, BelowTargetAltitudeClimbs) {
  AirframeParams airframe;
  VehicleState state;
  state.position_m = {0, 0, 1};
  const RotorSpeeds speeds =
      ComputeRotorSpeeds(airframe, ControllerGains{}, state, {0, 0}, 5.0, 0.0);
  double thrust;
  Eigen::Vector3d torque;
  Wrench(airframe, speeds, &thrust, &torque);
  EXPECT_GT(thrust, airframe.mass_kg * kG);
}

}  // namespace
}  // namespace sitlnet::flocker

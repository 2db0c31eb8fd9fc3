// The test autopilot's mission: climb to an altitude, hold it, fly to a waypoint (if any) at up
// to 2 m/s, with the flocker's cascaded controller and sitlnet's default quadrotor.
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PILOT_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PILOT_H_

#include <optional>

#include "robot_images/test_autopilot/simulator_link.h"

namespace sitlnet::test_autopilot {

struct Mission {
  double altitude_m = 10;                     // World z (above the origin's ground).
  std::optional<Eigen::Vector2d> waypoint_m;  // World x, y: flown to once at 80 % altitude.
};

class Pilot {
 public:
  explicit Pilot(const Mission& mission) : mission_(mission) {}
  // Motor outputs for the vehicle's state; the heading is held where the first state had it.
  MotorOutputs Fly(const flocker::VehicleState& state);

 private:
  Mission mission_;
  std::optional<double> yaw_rad_;
};

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PILOT_H_

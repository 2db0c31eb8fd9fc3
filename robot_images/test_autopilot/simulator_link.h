// What the test autopilot knows of its simulator, whichever protocol carries it: one observation
// per simulator message, answered by one set of motor outputs.
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_SIMULATOR_LINK_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_SIMULATOR_LINK_H_

#include <array>
#include <cstdint>

#include "robot_images/flocker/controller.h"

namespace sitlnet::test_autopilot {

struct Observation {
  double time_s = 0;               // The simulator's clock: the autopilot's clock.
  flocker::VehicleState state;     // What the autopilot estimates (world ENU, body FLU).
  Eigen::Vector3d true_position_m  // The simulator's ground truth, for --log-replies.
      = Eigen::Vector3d::Zero();
  bool ready_to_arm = false;  // The protocol gave what flying needs (a GPS fix, ...).
};

using MotorOutputs = std::array<double, 4>;  // 0..1, quad-X in ArduPilot's and PX4's order

class SimulatorLink {
 public:
  virtual ~SimulatorLink() = default;
  enum class Result { kObservation, kTimeout };
  // Waits up to `timeout_ms` for the next observation (resending what the protocol resends).
  // Ends the program with a message if the simulator goes away for good.
  virtual Result Wait(int timeout_ms, Observation* observation) = 0;
  // Answers the last observation.
  virtual void Answer(const MotorOutputs& motors, bool armed) = 0;
};

// NED/FRD (both autopilots' protocols) to ENU/FLU.
Eigen::Vector3d NedToEnu(const Eigen::Vector3d& ned);
Eigen::Vector3d FrdToFlu(const Eigen::Vector3d& frd);
// The attitude of body FRD in NED as the attitude of body FLU in ENU.
Eigen::Quaterniond FrdInNedToFluInEnu(const Eigen::Quaterniond& q);

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_SIMULATOR_LINK_H_

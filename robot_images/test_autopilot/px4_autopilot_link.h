// PX4's side of PX4's simulator MAVLink interface (docs/autopilots.md, "PX4 simulator
// interface"), as PX4 SITL's simulator_mavlink module speaks it: a TCP client of the simulator,
// MAVLink 2, one HIL_ACTUATOR_CONTROLS (lock-step flag set) answering each HIL_SENSOR with its
// time_usec, a HEARTBEAT every second of its clock.
//
// What it estimates, from the protocol alone: position and velocity from the latest HIL_GPS fix,
// carried forward to the sensor's time by the fix's velocity (GPS comes at 10 Hz, sensors at
// 250); body rates from HIL_SENSOR's gyro; attitude from HIL_STATE_QUATERNION, the simulator's
// ground truth, standing in for PX4's attitude estimator (so the test autopilot needs it, which
// sitlnet sends by default). An observation is complete when the ground truth of the sensor's
// time has arrived (sitlnet sends HIL_SENSOR, HIL_GPS, HIL_STATE_QUATERNION in that order).
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PX4_AUTOPILOT_LINK_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PX4_AUTOPILOT_LINK_H_

#include <netinet/in.h>

#include <optional>

#include "mavlink/mavlink.h"
#include "robot_images/test_autopilot/local_frame.h"
#include "robot_images/test_autopilot/simulator_link.h"

namespace sitlnet::test_autopilot {

class Px4Link : public SimulatorLink {
 public:
  // Connects to `server` (TCP), retrying every 100 ms for up to `connect_timeout_ms`, as PX4
  // waits for its simulator. `system_id`: PX4's MAV_SYS_ID (1 by default). `frame` must outlive
  // the link.
  Px4Link(const sockaddr_in& server, uint8_t system_id, const LocalFrame* frame,
          int connect_timeout_ms);
  ~Px4Link() override;
  Result Wait(int timeout_ms, Observation* observation) override;
  void Answer(const MotorOutputs& motors, bool armed) override;

 private:
  // Takes one frame; true when it completes an observation.
  bool Take(const mavlink::ReceivedFrame& frame, Observation* observation);
  void Write(const std::vector<uint8_t>& bytes);

  int fd_ = -1;
  uint8_t system_id_;
  const LocalFrame* frame_;
  mavlink::FrameParser parser_;
  uint8_t sequence_ = 0;
  std::optional<mavlink::HilSensor> sensor_;  // The latest, until its ground truth arrives.
  std::optional<mavlink::HilGps> fix_;        // The latest 3D fix.
  uint64_t answering_usec_ = 0;               // time_usec of the observation being answered.
  uint64_t next_heartbeat_usec_ = 0;
};

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_PX4_AUTOPILOT_LINK_H_

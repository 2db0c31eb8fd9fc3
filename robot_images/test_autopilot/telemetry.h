// The telemetry an autopilot sends its ground station, as MAVLink 2 over UDP (one message per
// datagram, as PX4 and ArduPilot send to a GCS on port 14550): HEARTBEAT every second of its
// clock, GLOBAL_POSITION_INT at a rate of its clock. Stamped with the autopilot's clock
// (time_boot_ms), so a test can tell when each entered the radio.
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_TELEMETRY_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_TELEMETRY_H_

#include <netinet/in.h>

#include <cstdint>

#include "robot_images/test_autopilot/local_frame.h"
#include "robot_images/test_autopilot/simulator_link.h"

namespace sitlnet::test_autopilot {

class Telemetry {
 public:
  // Sends to `to` from port to.sin_port. `frame` must outlive the telemetry.
  Telemetry(const sockaddr_in& to, uint8_t system_id, const LocalFrame* frame, double rate_hz);
  ~Telemetry();
  // Sends what is due at the observation's time.
  void Update(const Observation& observation, bool armed);

 private:
  void Send(const std::vector<uint8_t>& bytes);

  int fd_ = -1;
  sockaddr_in to_;
  uint8_t system_id_;
  const LocalFrame* frame_;
  double period_s_;
  double next_position_s_ = 0;
  double next_heartbeat_s_ = 0;
  uint8_t sequence_ = 0;
};

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_TELEMETRY_H_

// ArduPilot's JSON physics protocol, client side, as ArduPilot SITL speaks it (docs/protocols.md):
// a 40-byte servo frame with an increasing frame_count, then a wait for the JSON reply whose
// timestamp is the autopilot's clock; the same frame again when no reply comes within a second.
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_JSON_AUTOPILOT_LINK_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_JSON_AUTOPILOT_LINK_H_

#include <netinet/in.h>

#include <string>

#include "robot_images/test_autopilot/simulator_link.h"

namespace sitlnet::test_autopilot {

class JsonLink : public SimulatorLink {
 public:
  // Sends the first frame (motors stopped) to `server`.
  JsonLink(const sockaddr_in& server, uint16_t frame_rate_hz);
  ~JsonLink() override;
  Result Wait(int timeout_ms, Observation* observation) override;
  void Answer(const MotorOutputs& motors, bool armed) override;

 private:
  int fd_ = -1;
  uint16_t frame_rate_hz_;
  uint32_t frame_count_ = 1;
  std::string frame_;  // The last frame sent: resent after a second without a reply.
  int waited_ms_ = 0;
};

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_JSON_AUTOPILOT_LINK_H_

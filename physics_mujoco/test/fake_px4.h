// PX4's side of the simulator link for tests: a TCP client that sends what PX4 sends and
// parses what the simulator answers.
#ifndef SITLNET_PHYSICS_MUJOCO_TEST_FAKE_PX4_H_
#define SITLNET_PHYSICS_MUJOCO_TEST_FAKE_PX4_H_

#include <cstdint>
#include <vector>

#include "common/common.h"
#include "mavlink/mavlink.h"

namespace sitlnet::physics::testing {

class FakePx4 {
 public:
  // Connects to address:port (blocking); fails the test if it cannot.
  FakePx4(Ipv4 address, uint16_t port);
  ~FakePx4();
  FakePx4(const FakePx4&) = delete;
  FakePx4& operator=(const FakePx4&) = delete;

  void Write(const std::vector<uint8_t>& bytes);
  // A HIL_ACTUATOR_CONTROLS with all four motors at `throttle`, lock-step flag set.
  void SendControls(uint64_t time_usec, float throttle, bool armed);
  // Reads until a frame of message `id` arrives (waiting on the socket, 5 s at most).
  mavlink::ReceivedFrame Receive(uint32_t id);
  // Every byte received so far (Receive keeps them).
  const std::vector<uint8_t>& received() const { return received_; }

 private:
  int fd_ = -1;
  mavlink::FrameParser parser_;
  std::vector<uint8_t> received_;
};

}  // namespace sitlnet::physics::testing

#endif  // SITLNET_PHYSICS_MUJOCO_TEST_FAKE_PX4_H_

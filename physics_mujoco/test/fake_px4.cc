#include "physics_mujoco/test/fake_px4.h"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "mavlink/mavlink.h"
#include "physics_mujoco/udp_socket.h"

namespace sitlnet::physics::testing {

FakePx4::FakePx4(Ipv4 address, uint16_t port) {
  fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const sockaddr_in sa = MakeSockaddr(address, port);
  EXPECT_EQ(connect(fd_, reinterpret_cast<const sockaddr*>(&sa), sizeof sa), 0);
}

FakePx4::~FakePx4() { close(fd_); }

void FakePx4::Write(const std::vector<uint8_t>& bytes) {
  ASSERT_EQ(send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL),
            static_cast<ssize_t>(bytes.size()));
}

void FakePx4::SendControls(uint64_t time_usec, float throttle, bool armed) {
  mavlink::HilActuatorControls controls;
  controls.time_usec = time_usec;
  controls.controls = {throttle, throttle, throttle, throttle};
  controls.mode = 1 | (armed ? mavlink::kModeFlagSafetyArmed : 0);
  controls.flags = mavlink::kActuatorFlagLockstep;
  std::vector<uint8_t> bytes;
  mavlink::AppendMessage(controls, {0, 1, 1}, &bytes);
  Write(bytes);
}

mavlink::ReceivedFrame FakePx4::Receive(uint32_t id) {
  mavlink::ReceivedFrame frame;
  for (;;) {
    while (parser_.Next(&frame)) {
      if (frame.message_id == id) return frame;
    }
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, 5000) != 1) {
      ADD_FAILURE() << "no message " << id << " within 5 s";
      return frame;
    }
    uint8_t buffer[4096];
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) {
      ADD_FAILURE() << "connection closed";
      return frame;
    }
    received_.insert(received_.end(), buffer, buffer + n);
    parser_.Push(buffer, static_cast<size_t>(n));
  }
}

}  // namespace sitlnet::physics::testing

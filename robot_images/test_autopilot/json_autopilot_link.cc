#include "robot_images/test_autopilot/json_autopilot_link.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sitlnet::test_autopilot {
namespace {

constexpr int kResendAfterMs = 1000;  // As SITL does: the same frame again after a second.

// The servo frame of ArduPilot's JSON backend: magic 18458, frame rate, frame count, 16 PWMs
// (µs), little-endian. Motor output u is PWM 1000 + 1000 u; other channels at 1500.
std::string ServoFrame(uint16_t rate_hz, uint32_t frame_count, const MotorOutputs& motors) {
  std::string bytes(40, '\0');
  const auto put16 = [&](int at, uint16_t v) {
    bytes[at] = static_cast<char>(v & 0xff);
    bytes[at + 1] = static_cast<char>(v >> 8);
  };
  put16(0, 18458);
  put16(2, rate_hz);
  for (int i = 0; i < 4; ++i) bytes[4 + i] = static_cast<char>((frame_count >> (8 * i)) & 0xff);
  for (int channel = 0; channel < 16; ++channel) {
    const double pwm = channel < 4 ? 1000 + 1000 * std::clamp(motors[channel], 0.0, 1.0) : 1500;
    put16(8 + 2 * channel, static_cast<uint16_t>(pwm));
  }
  return bytes;
}

// The numbers of `"key":` (one, or an array) in the reply, as ArduPilot's parser finds keys.
bool ReadNumbers(const std::string& json, const char* key, double* out, int count) {
  const std::string quoted = std::string("\"") + key + "\":";
  const size_t at = json.find(quoted);
  if (at == std::string::npos) return false;
  const char* p = json.c_str() + at + quoted.size();
  if (count > 1 && *p++ != '[') return false;
  for (int i = 0; i < count; ++i) {
    char* end = nullptr;
    out[i] = std::strtod(p, &end);
    if (end == p) return false;
    p = end + 1;
  }
  return true;
}

bool ParseReply(const std::string& json, Observation* observation) {
  double t = 0, gyro[3], position[3], velocity[3], q[4];
  if (!ReadNumbers(json, "timestamp", &t, 1) || !ReadNumbers(json, "gyro", gyro, 3) ||
      !ReadNumbers(json, "position", position, 3) || !ReadNumbers(json, "velocity", velocity, 3) ||
      !ReadNumbers(json, "quaternion", q, 4)) {
    return false;
  }
  observation->time_s = t;
  flocker::VehicleState& state = observation->state;
  state.position_m = NedToEnu({position[0], position[1], position[2]});
  state.velocity_m_s = NedToEnu({velocity[0], velocity[1], velocity[2]});
  state.angular_velocity_rad_s = FrdToFlu({gyro[0], gyro[1], gyro[2]});
  state.orientation = FrdInNedToFluInEnu(Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
  observation->true_position_m = state.position_m;  // The protocol gives the truth.
  observation->ready_to_arm = true;
  return true;
}

}  // namespace

JsonLink::JsonLink(const sockaddr_in& server, uint16_t frame_rate_hz)
    : frame_rate_hz_(frame_rate_hz) {
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0 || connect(fd_, reinterpret_cast<const sockaddr*>(&server), sizeof server) != 0) {
    std::fprintf(stderr, "test_autopilot: JSON socket: %s\n", std::strerror(errno));
    std::exit(2);
  }
  frame_ = ServoFrame(frame_rate_hz_, frame_count_, {0, 0, 0, 0});
  send(fd_, frame_.data(), frame_.size(), 0);
}

JsonLink::~JsonLink() { close(fd_); }

SimulatorLink::Result JsonLink::Wait(int timeout_ms, Observation* observation) {
  pollfd wait{fd_, POLLIN, 0};
  if (poll(&wait, 1, timeout_ms) <= 0) {
    waited_ms_ += timeout_ms;
    if (waited_ms_ >= kResendAfterMs) {
      send(fd_, frame_.data(), frame_.size(), 0);
      waited_ms_ = 0;
    }
    return Result::kTimeout;
  }
  waited_ms_ = 0;
  char buffer[2048];
  const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
  if (n <= 0 || !ParseReply(std::string(buffer, n), observation)) return Result::kTimeout;
  return Result::kObservation;
}

void JsonLink::Answer(const MotorOutputs& motors, bool armed) {
  // ArduPilot sends PWM 1000 (motors stopped) while disarmed.
  frame_ = ServoFrame(frame_rate_hz_, ++frame_count_, armed ? motors : MotorOutputs{});
  send(fd_, frame_.data(), frame_.size(), 0);
}

}  // namespace sitlnet::test_autopilot

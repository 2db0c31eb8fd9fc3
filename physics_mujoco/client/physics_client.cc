#include "physics_mujoco/client/physics_client.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <utility>

namespace sitlnet::physics_client {
namespace {

sockaddr_in ParseEndpoint(const std::string& text, bool need_port) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  std::string host = text;
  if (need_port) {
    const size_t colon = text.rfind(':');
    if (colon == std::string::npos) {
      throw std::runtime_error("physics client: \"" + text + "\" is not a.b.c.d:port");
    }
    host = text.substr(0, colon);
    char* end = nullptr;
    const long port = std::strtol(text.c_str() + colon + 1, &end, 10);
    if (*end != '\0' || port < 1 || port > 65535) {
      throw std::runtime_error("physics client: bad port in \"" + text + "\"");
    }
    sa.sin_port = htons(static_cast<uint16_t>(port));
  }
  if (inet_pton(AF_INET, host.c_str(), &sa.sin_addr) != 1) {
    throw std::runtime_error("physics client: \"" + host + "\" is not an IPv4 address");
  }
  return sa;
}

std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

PhysicsClient::PhysicsClient(const std::string& server, const std::string& bind_address) {
  const sockaddr_in remote = ParseEndpoint(server, true);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(Errno("physics client: socket"));
  if (!bind_address.empty()) {
    const sockaddr_in local = ParseEndpoint(bind_address, false);
    if (bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
      const std::string message = Errno("physics client: bind " + bind_address);
      close(fd_);
      throw std::runtime_error(message);
    }
  }
  // connect(): the kernel picks ctl0's address and delivers only the server's datagrams.
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&remote), sizeof remote) != 0) {
    const std::string message = Errno("physics client: connect " + server);
    close(fd_);
    throw std::runtime_error(message);
  }
}

PhysicsClient PhysicsClient::FromEnvironment() {
  const char* server = std::getenv(kServerAddressEnv);
  if (server == nullptr || *server == '\0') {
    throw std::runtime_error(std::string("physics client: ") + kServerAddressEnv + " is not set");
  }
  PhysicsClient client(server);
  if (const char* index = std::getenv(kRobotIndexEnv); index != nullptr && *index != '\0') {
    client.set_robot_index(static_cast<uint32_t>(std::strtoul(index, nullptr, 10)));
  }
  return client;
}

PhysicsClient::~PhysicsClient() {
  if (fd_ >= 0) close(fd_);
}

PhysicsClient::PhysicsClient(PhysicsClient&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), robot_index_(other.robot_index_) {}

PhysicsClient& PhysicsClient::operator=(PhysicsClient&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    robot_index_ = other.robot_index_;
  }
  return *this;
}

bool PhysicsClient::Send(const proto::MotorCommand& command) {
  command.SerializeToString(&buffer_);
  return send(fd_, buffer_.data(), buffer_.size(), 0) == static_cast<ssize_t>(buffer_.size());
}

bool PhysicsClient::SendRotorSpeeds(const std::array<double, 4>& speeds_rad_s, uint64_t step) {
  proto::MotorCommand command;
  if (robot_index_) command.set_robot(*robot_index_);
  command.set_step(step);
  for (double speed : speeds_rad_s) command.add_rotor_speed_rad_s(speed);
  return Send(command);
}

bool PhysicsClient::SendThrottles(const std::array<double, 4>& throttles, uint64_t step) {
  proto::MotorCommand command;
  if (robot_index_) command.set_robot(*robot_index_);
  command.set_step(step);
  for (double throttle : throttles) command.add_throttle(throttle);
  return Send(command);
}

bool PhysicsClient::Receive(proto::RobotState* state, int timeout_ms) {
  char buffer[4096];
  // Deadline, so that datagrams that do not parse cannot extend the wait.
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  const int64_t deadline_ms = now.tv_sec * 1000 + now.tv_nsec / 1000000 + timeout_ms;
  for (;;) {
    int wait_ms = timeout_ms;
    if (timeout_ms > 0) {
      clock_gettime(CLOCK_MONOTONIC, &now);
      wait_ms = static_cast<int>(
          std::max<int64_t>(0, deadline_ms - (now.tv_sec * 1000 + now.tv_nsec / 1000000)));
    }
    pollfd fd{fd_, POLLIN, 0};
    const int ready = poll(&fd, 1, wait_ms);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    const ssize_t n = recv(fd_, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n > 0 && state->ParseFromArray(buffer, static_cast<int>(n))) return true;
    // A refused send (no server yet) surfaces here as ECONNREFUSED: keep waiting.
  }
}

bool PhysicsClient::ReceiveLatest(proto::RobotState* state, int timeout_ms) {
  if (!Receive(state, timeout_ms)) return false;
  while (Receive(state, 0)) {
  }
  return true;
}

}  // namespace sitlnet::physics_client

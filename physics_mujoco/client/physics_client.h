// sitlnet physics client: what onboard robot software links (with protobuf) to fly its
// simulated multirotor over ctl0. Protocol and frames: docs/protocols.md,
// proto/sitlnet/robot.proto.
//
//   sitlnet::physics_client::PhysicsClient client = PhysicsClient::FromEnvironment();
//   client.SendRotorSpeeds({w1, w2, w3, w4});     // holds until replaced
//   sitlnet::proto::RobotState state;
//   if (client.Receive(&state, 100)) { ... }       // at the robot's state rate
#ifndef SITLNET_PHYSICS_MUJOCO_CLIENT_PHYSICS_CLIENT_H_
#define SITLNET_PHYSICS_MUJOCO_CLIENT_PHYSICS_CLIENT_H_

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "sitlnet/robot.pb.h"

namespace sitlnet::physics_client {

// Environment variable holding the server's "a.b.c.d:port" (set by `sitlnet up`/`exec`).
inline constexpr char kServerAddressEnv[] = "SITLNET_PHYSICS_ADDR";
// Optional environment variable with the robot's index, copied into MotorCommand.robot.
inline constexpr char kRobotIndexEnv[] = "SITLNET_ROBOT_INDEX";

class PhysicsClient {
 public:
  // Opens a UDP socket connected to `server` ("a.b.c.d:port"). `bind_address` (dotted quad,
  // may be empty) fixes the local address; normally the kernel picks ctl0's. Throws
  // std::runtime_error with a one-line reason.
  explicit PhysicsClient(const std::string& server, const std::string& bind_address = "");
  // Server from SITLNET_PHYSICS_ADDR, robot index from SITLNET_ROBOT_INDEX if set.
  static PhysicsClient FromEnvironment();
  ~PhysicsClient();
  PhysicsClient(PhysicsClient&& other) noexcept;
  PhysicsClient& operator=(PhysicsClient&& other) noexcept;
  PhysicsClient(const PhysicsClient&) = delete;
  PhysicsClient& operator=(const PhysicsClient&) = delete;

  // Sets MotorCommand.robot on every command (the server checks it); unset: not sent.
  void set_robot_index(std::optional<uint32_t> index) { robot_index_ = index; }

  // Target rotor speeds (rad/s, ArduPilot quad-X order) or throttles in [0, 1]. `step` is
  // echoed in RobotState.command_step. Return false if the kernel refused the datagram.
  bool SendRotorSpeeds(const std::array<double, 4>& speeds_rad_s, uint64_t step = 0);
  bool SendThrottles(const std::array<double, 4>& throttles, uint64_t step = 0);
  bool Send(const proto::MotorCommand& command);

  // Waits up to `timeout_ms` (< 0: forever) for the next RobotState. False on timeout.
  // Datagrams that do not parse are skipped.
  bool Receive(proto::RobotState* state, int timeout_ms);
  // Like Receive, but drains what is queued and keeps the newest state.
  bool ReceiveLatest(proto::RobotState* state, int timeout_ms);

  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::optional<uint32_t> robot_index_;
  std::string buffer_;
};

}  // namespace sitlnet::physics_client

#endif  // SITLNET_PHYSICS_MUJOCO_CLIENT_PHYSICS_CLIENT_H_

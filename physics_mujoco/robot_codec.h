// Native robot <-> physics protocol codec: MotorCommand validation, RobotState filling.
// The sockets and the per-robot state live in physics_server.cc.
#ifndef SITLNET_PHYSICS_MUJOCO_ROBOT_CODEC_H_
#define SITLNET_PHYSICS_MUJOCO_ROBOT_CODEC_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "sitlnet/robot.pb.h"

namespace sitlnet::physics {

enum class CommandVerdict {
  kAccepted,
  kMalformed,   // Not a parseable MotorCommand.
  kInvalid,     // Not exactly one of rotor_speed_rad_s / throttle with 4 finite in-range values.
  kWrongRobot,  // robot set and not ours.
};

struct DecodedCommand {
  RotorSpeeds target_rad_s{};
  uint64_t step = 0;
};

// Decodes and validates one datagram for robot `robot_index` whose rotors top out at
// `max_speed_rad_s`. Out-of-range values are rejected, not clamped: a robot sending them has
// a bug worth counting.
CommandVerdict DecodeMotorCommand(const void* data, size_t size, int robot_index,
                                  double max_speed_rad_s, DecodedCommand* command);

// Fills `state` for robot `robot_index` (IMU sample and lidar ranges given).
void FillRobotState(int robot_index, int64_t steps, TimeNs sim_time_ns, const RobotPose& pose,
                    const ImuSample& imu, const std::vector<float>& lidar_m,
                    const RotorSpeeds& speeds, uint64_t command_step, bool motors_cut,
                    proto::RobotState* state);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_ROBOT_CODEC_H_

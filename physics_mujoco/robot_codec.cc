#include "physics_mujoco/robot_codec.h"

#include <cmath>

namespace sitlnet::physics {
namespace {

void SetVector(const Vec3d& v, proto::RobotState::Vector3* out) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

}  // namespace

CommandVerdict DecodeMotorCommand(const void* data, size_t size, int robot_index,
                                  double max_speed_rad_s, DecodedCommand* command) {
  proto::MotorCommand message;
  if (size == 0 || !message.ParseFromArray(data, static_cast<int>(size))) {
    return CommandVerdict::kMalformed;
  }
  if (message.has_robot() && message.robot() != static_cast<uint32_t>(robot_index)) {
    return CommandVerdict::kWrongRobot;
  }
  const bool speeds = message.rotor_speed_rad_s_size() > 0;
  const bool throttles = message.throttle_size() > 0;
  if (speeds == throttles) return CommandVerdict::kInvalid;
  const auto& values = speeds ? message.rotor_speed_rad_s() : message.throttle();
  if (values.size() != kRotors) return CommandVerdict::kInvalid;
  const double max = speeds ? max_speed_rad_s : 1.0;
  for (int i = 0; i < kRotors; ++i) {
    const double value = values[i];
    // !(a <= b) also rejects NaN.
    if (!(value >= 0 && value <= max)) return CommandVerdict::kInvalid;
    command->target_rad_s[i] = speeds ? value : value * max_speed_rad_s;
  }
  command->step = message.step();
  return CommandVerdict::kAccepted;
}

void FillRobotState(int robot_index, int64_t steps, TimeNs sim_time_ns, const RobotPose& pose,
                    const ImuSample& imu, const std::vector<float>& lidar_m,
                    const RotorSpeeds& speeds, uint64_t command_step, bool motors_cut,
                    proto::RobotState* state) {
  state->Clear();
  state->set_robot(static_cast<uint32_t>(robot_index));
  state->set_step(static_cast<uint64_t>(steps));
  state->set_sim_time_ns(sim_time_ns);
  SetVector(pose.position_m, state->mutable_position_m());
  auto* q = state->mutable_orientation();
  q->set_w(pose.orientation.w);
  q->set_x(pose.orientation.x);
  q->set_y(pose.orientation.y);
  q->set_z(pose.orientation.z);
  SetVector(pose.velocity_m_s, state->mutable_velocity_m_s());
  SetVector(pose.angular_velocity_rad_s, state->mutable_angular_velocity_rad_s());
  SetVector(imu.gyro_rad_s, state->mutable_gyro_rad_s());
  SetVector(imu.accel_m_s2, state->mutable_accel_m_s2());
  for (float range : lidar_m) state->add_lidar_range_m(range);
  for (double speed : speeds) state->add_rotor_speed_rad_s(speed);
  state->set_command_step(command_step);
  state->set_motors_cut(motors_cut);
}

}  // namespace sitlnet::physics

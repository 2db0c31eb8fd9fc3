#include "physics_mujoco/px4_robot.h"

#include "physics_mujoco/px4_messages.h"

namespace sitlnet::physics {

Px4Robot::Px4Robot(const Scenario& scenario, int robot, uint16_t port, const GeodeticFrame* frame,
                   const Px4RobotOptions& options)
    : robot_(robot),
      spec_(&scenario.robots.at(robot).spec),
      options_(options),
      frame_(frame),
      link_(scenario.robots.at(robot).ctl_root_address, port,
            scenario.robots.at(robot).airframe.max_rotor_speed_rad_s(),
            "robot \"" + scenario.robots.at(robot).name + "\": PX4 simulator link"),
      sensors_(scenario.robots.at(robot).spec, scenario.spec.geodetic_origin(), frame,
               scenario.spec.timing().seed(), robot) {
  SITLNET_DEMAND(options_.sensor_period_ns > 0);
}

bool Px4Robot::PollLink(World* world) {
  const bool reconnected = AcceptLink(world);
  link_.Read();
  return reconnected;
}

bool Px4Robot::AcceptLink(World* world) {
  if (link_.Accept() != Px4SimulatorLink::Event::kReconnected) return false;
  // A restarted PX4 expects a vehicle at rest at its start: the robot starts over (the clock
  // goes on), with the same sensor noise as the first time.
  world->ResetRobot(robot_);
  sensors_.Reset();
  return true;
}

bool Px4Robot::Step(World* world, TimeNs time_ns) {
  PollLink(world);
  return SendDue(world, time_ns);
}

bool Px4Robot::SendDue(World* world, TimeNs time_ns) {
  if (time_ns < next_sensor_ns_) return false;
  next_sensor_ns_ +=
      options_.sensor_period_ns * ((time_ns - next_sensor_ns_) / options_.sensor_period_ns + 1);
  if (!link_.connected()) return false;
  const RobotPose pose = world->Pose(robot_);
  const ImuSample imu = world->Imu(robot_);
  const mavlink::HilSensor sensor = MakeHilSensor(
      time_ns, imu, sensors_.Magnetometer(pose.orientation), sensors_.Barometer(pose.position_m.z));
  std::optional<mavlink::HilGps> gps;
  if (const std::optional<GpsFix> fix = sensors_.DeliveredGps(time_ns, pose)) {
    gps = MakeHilGps(fix->sampled_ns, *fix, spec_->gps());  // As Gazebo: stamped when measured.
  }
  std::optional<mavlink::HilStateQuaternion> truth;
  if (options_.send_ground_truth) truth = MakeGroundTruth(time_ns, pose, imu, *frame_);
  link_.Send(sensor, gps ? &*gps : nullptr, truth ? &*truth : nullptr);
  return true;
}

void Px4Robot::ApplyCommand(World* world) {
  PollLink(world);
  world->SetRotorTarget(robot_, link_.command().rotor_speeds_rad_s);
}

}  // namespace sitlnet::physics

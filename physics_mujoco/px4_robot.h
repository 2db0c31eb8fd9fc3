// One World robot flown by PX4 through its simulator interface: the link, the robot's sensor
// models, and the step that joins them to the World (docs/autopilots.md). Clock-agnostic: the
// driver calls Step with the robot's virtual time after each physics advance.
#ifndef SITLNET_PHYSICS_MUJOCO_PX4_ROBOT_H_
#define SITLNET_PHYSICS_MUJOCO_PX4_ROBOT_H_

#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/px4_simulator_link.h"
#include "physics_mujoco/sensor_models.h"

namespace sitlnet::physics {

struct Px4RobotOptions {
  // HIL_SENSOR rate in virtual time: PX4 SITL's Gazebo worlds step, and send, every 4 ms.
  TimeNs sensor_period_ns = 4 * kNsPerMs;
  bool send_ground_truth = true;  // HIL_STATE_QUATERNION with each HIL_SENSOR (PX4 asks for it)
};

class Px4Robot {
 public:
  // Listens on the robot's ctl0 root address at `port` (Px4SimulatorLink). `scenario` and
  // `frame` must outlive the robot.
  Px4Robot(const Scenario& scenario, int robot, uint16_t port, const GeodeticFrame* frame,
           const Px4RobotOptions& options = {});

  // At virtual time `time_ns` (the robot's state in `world` is that time's): takes what PX4
  // sent, resets the robot if PX4 reconnected, and when a sensor message is due (on the grid
  // 0, period, 2 period, ...) sends it from the world's pose and IMU. Returns true if it sent.
  bool Step(World* world, TimeNs time_ns);
  // Step without taking what PX4 sent: for a caller that reads the link when epoll says it is
  // readable (PhysicsServer), so a step costs no system call beyond the send.
  bool SendDue(World* world, TimeNs time_ns);
  // Takes what PX4 sent and sets the robot's rotor targets from PX4's latest command.
  void ApplyCommand(World* world);
  // Takes what PX4 sent (accepting a new connection; resetting the robot if PX4 reconnected).
  // Returns true if it reconnected.
  bool PollLink(World* world);
  // PollLink's halves: a new connection (the listener is readable), or what arrived on the
  // connection. AcceptLink returns true if PX4 reconnected (the robot was reset).
  bool AcceptLink(World* world);
  void ReadLink() { link_.Read(); }
  // Virtual time of the next sensor message (the grid 0, period, 2 period, ...).
  TimeNs next_sensor_ns() const { return next_sensor_ns_; }
  TimeNs sensor_period_ns() const { return options_.sensor_period_ns; }

  Px4SimulatorLink& link() { return link_; }
  const Px4SimulatorLink& link() const { return link_; }
  int robot() const { return robot_; }

 private:
  int robot_;
  const proto::Robot* spec_;
  Px4RobotOptions options_;
  const GeodeticFrame* frame_;
  Px4SimulatorLink link_;
  HilSensorModel sensors_;
  TimeNs next_sensor_ns_ = 0;
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_PX4_ROBOT_H_

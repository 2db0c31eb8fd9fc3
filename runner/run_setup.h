// The setup stage of `sitlnet run`: the scenario's namespaces, the physics server, the medium
// (bridge and its records), the ground station's GCS relay and the robots' images, brought up in
// that order and torn down in the reverse order however the run ends.
#ifndef SITLNET_RUNNER_RUN_SETUP_H_
#define SITLNET_RUNNER_RUN_SETUP_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "network_side/network_side.h"
#include "physics_mujoco/physics_mujoco.h"
#include "robot_images/robot_images.h"
#include "ros2_clock/ros2_clock.h"
#include "runner/medium_records.h"
#include "runner/robot_host.h"
#include "runner/robot_slot.h"
#include "runner/run_medium.h"
#include "runner/run_parts.h"
#include "runner/runner.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

class RunSetup final : public RunParts {
 public:
  // Brings everything up, ready for iteration 0 (in lockstep, and in realtime with
  // wait_for_robots, every image has spoken to physics). `remote`: the accepted remote medium
  // (--remote network), or null for the medium in this process. Throws Error; whatever was up by
  // then is torn down. `scenario` and `options` must outlive this.
  RunSetup(const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
           std::unique_ptr<network_side::RemoteMedium> remote);
  RunSetup(const RunSetup&) = delete;
  RunSetup& operator=(const RunSetup&) = delete;
  ~RunSetup();

  const Scenario& scenario() const override { return scenario_; }
  bool lockstep() const override { return lockstep_; }
  physics::PhysicsServer& physics_server() { return *physics_server_; }
  const physics::PhysicsServer* local_physics() const override { return physics_server_.get(); }
  tapbridge::BridgeCore& bridge() override { return medium_->bridge(); }
  MediumRecords& medium_records() override { return medium_->records(); }
  std::vector<RobotSlot>& robots() override { return robots_; }
  clock::Timebase& run_timebase() override { return run_timebase_; }
  // The virtual time the robots' /clock publishers read; null without timing.ros2_clock_hz.
  ros2_clock::SharedVirtualTime* shared_time() { return shared_time_ ? &*shared_time_ : nullptr; }
  std::vector<std::unique_ptr<images::RobotProcess>>& clock_publishers() {
    return clock_publishers_;
  }
  network_side::RemoteMedium* remote_medium() override { return medium_->remote_medium(); }
  gcs::GcsRelay* gcs_relay() override { return gcs_relay_.get(); }

 private:
  // The stages of the setup, in the order the constructor calls them.
  void BringUpNamespaces();
  void StartPhysics();
  void StartMedium();
  void StartGcsRelay();
  void StartRobots();

  const Scenario& scenario_;
  const RunOptions& options_;
  const std::string run_dir_;
  const bool lockstep_;
  // Until the bridge takes it: dropped on a failure before, it tells the remote side why.
  std::unique_ptr<network_side::RemoteMedium> remote_owned_;
  // Members are destroyed in the reverse order: images, then the medium, physics, namespaces.
  std::unique_ptr<ScenarioNamespaces> namespaces_;
  clock::Timebase run_timebase_;
  std::unique_ptr<physics::PhysicsServer> physics_server_;
  std::unique_ptr<RunMedium> medium_;
  // Before the images, so that the vehicles' first datagrams find the station's port bound.
  std::unique_ptr<gcs::GcsRelay> gcs_relay_;
  std::vector<RobotSlot> robots_;
  std::optional<ros2_clock::SharedVirtualTime> shared_time_;
  std::vector<std::unique_ptr<images::RobotProcess>> clock_publishers_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_SETUP_H_

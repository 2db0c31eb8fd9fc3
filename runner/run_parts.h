// What the run and report stages of `sitlnet run` use of a run's setup, whether every robot runs
// here (RunSetup) or the robots run on node hosts and only the medium runs here (FleetSetup,
// runner/fleet_run.cc; issue 35).
#ifndef SITLNET_RUNNER_RUN_PARTS_H_
#define SITLNET_RUNNER_RUN_PARTS_H_

#include <optional>
#include <vector>

#include "clock/clock.h"
#include "coordinator/coordinator.h"
#include "gcs_link/gcs_link.h"
#include "network_side/network_side.h"
#include "physics_mujoco/physics_mujoco.h"
#include "run_formats/run_formats.h"
#include "runner/medium_records.h"
#include "runner/robot_slot.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

class RunParts {
 public:
  virtual ~RunParts() = default;
  virtual const Scenario& scenario() const = 0;
  virtual bool lockstep() const = 0;
  virtual tapbridge::BridgeCore& bridge() = 0;
  virtual MediumRecords& medium_records() = 0;
  // One slot per robot of the scenario; those on node hosts have no process here.
  virtual std::vector<RobotSlot>& robots() = 0;
  // The run's timebase: the coordinator begins it before iteration 0 (realtime pacing).
  virtual clock::Timebase& run_timebase() = 0;
  // The medium on another host (owned by the bridge), or null.
  virtual network_side::RemoteMedium* remote_medium() = 0;
  // The physics server of this process; null when the physics runs on node hosts.
  virtual const physics::PhysicsServer* local_physics() const = 0;
  // The ground station's GCS relay (runner/gcs_relay_stage.h), or null.
  virtual gcs::GcsRelay* gcs_relay() { return nullptr; }
};

// The physics side as the coordinator drives it, recording trajectories.csv.
class RunPhysics {
 public:
  virtual ~RunPhysics() = default;
  virtual coordinator::Connector& connector() = 0;
  // Writes what trajectories.csv holds so far; throws Error naming the file.
  virtual void Flush() = 0;
  // The closest two robots came at trajectories.csv's samples; null with fewer than two robots.
  virtual std::optional<run_formats::ClosestApproach> closest_approach() const = 0;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_PARTS_H_

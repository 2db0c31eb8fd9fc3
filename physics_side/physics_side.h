// sitlnet physics side: the robots' lock-step with MuJoCo physics, as the coordinator's physics
// simulator. Over physics_mujoco: the pure World (tests, the correctness check) and the
// PhysicsServer that also serves the robots' ctl0 protocol (real runs). Each iteration advances
// N_phy = Δ/δ_phy steps and reports every robot's pose at the iteration's end. The coordinator
// steps this side and the network side (network_side/) on its clock; neither knows the other.
#ifndef SITLNET_PHYSICS_SIDE_PHYSICS_SIDE_H_
#define SITLNET_PHYSICS_SIDE_PHYSICS_SIDE_H_

#include <string>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"
#include "coordinator/connector.h"
#include "physics_mujoco/physics_mujoco.h"
#include "scenario/scenario.h"

namespace sitlnet::physics_side {

using coordinator::IterationContext;
using coordinator::Simulator;

// Appends the position (ENU m), orientation (w, x, y, z) and velocity (ENU m/s) of every robot
// the world simulates, in ascending global index.
void PosesFromWorld(const physics::World& world, proto::coord::Poses* poses);

// Steps a World (not owned, must outlive this).
class WorldSimulator final : public Simulator {
 public:
  WorldSimulator(const Scenario& scenario, physics::World* world)
      : world_(*world), steps_(scenario.physics_steps_per_iteration) {}
  proto::coord::Poses InitialPoses() override;
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  physics::World& world_;
  int steps_;
};

// The robot-facing lock-step (docs/coordinator.md, "lockstep"): each
// iteration sends every robot its state, waits for every robot's command for
// that state, reports CommandsCollected, then steps.
struct RobotLockstepOptions {
  bool enabled = false;
  // Wall time a robot may take to answer a state. Past it the run stops with
  // the robot's name (robots that never sent a command are not waited for).
  TimeNs command_timeout_ns = 1 * kNsPerS;
  // A robot past the timeout is dropped (PhysicsServer::DropFromLockstep:
  // motors cut, the run goes on) instead of stopping the run.
  bool drop_silent = false;
};

// Steps a PhysicsServer (not owned): robots get their RobotState and their
// commands are applied as in the server's own Advance(); with lock-step
// robots, as described above.
class PhysicsServerSimulator final : public Simulator {
 public:
  PhysicsServerSimulator(const Scenario& scenario, physics::PhysicsServer* server,
                         RobotLockstepOptions lockstep = {});
  proto::coord::Poses InitialPoses() override;
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  // The scenario's on_silent_robot policy for robots that missed the lock-step's timeout:
  // dropped (one line each) or the run stops (Error naming them): they did not answer `what`
  // `with` what they should have sent.
  void ApplySilentRobotPolicy(const std::vector<int>& silent, const std::string& what,
                              const std::string& with, const proto::coord::Start& start);

  physics::PhysicsServer& server_;
  int steps_;
  RobotLockstepOptions lockstep_;
  std::vector<std::string> robot_names_;
};

}  // namespace sitlnet::physics_side

#endif  // SITLNET_PHYSICS_SIDE_PHYSICS_SIDE_H_

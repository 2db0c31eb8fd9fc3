// Physics connectors over physics_mujoco: the pure World (tests, the
// correctness check) and the PhysicsServer that also serves the robots'
// ctl0 protocol (real runs). Each iteration advances N_phy = Δ/δ_phy steps
// and reports every robot's pose at the iteration's end.
#ifndef SITLNET_COORDINATOR_PHYSICS_CONNECTOR_H_
#define SITLNET_COORDINATOR_PHYSICS_CONNECTOR_H_

#include "coordinator/connector.h"
#include "physics_mujoco/physics_mujoco.h"
#include "scenario/scenario.h"

namespace sitlnet::coordinator {

// Appends every robot's position (ENU m) and orientation (w, x, y, z).
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

// Steps a PhysicsServer (not owned): robots get their state and their
// commands are applied as the server's Advance() does in standalone mode.
// The robot-facing lock-step handshake (state k to every robot, wait for
// every command k, then CommandsCollected) needs a blocking "collect
// commands" call in PhysicsServer, which it does not have yet: until then
// this connector never reports CommandsCollected (docs/coordinator.md).
class PhysicsServerSimulator final : public Simulator {
 public:
  PhysicsServerSimulator(const Scenario& scenario, physics::PhysicsServer* server)
      : server_(*server), steps_(scenario.physics_steps_per_iteration) {}
  proto::coord::Poses InitialPoses() override;
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  physics::PhysicsServer& server_;
  int steps_;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_PHYSICS_CONNECTOR_H_

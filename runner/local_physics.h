// The physics side of a run whose robots all run here: the setup's physics server, stepped on
// its own thread, recording trajectories.csv.
#ifndef SITLNET_RUNNER_LOCAL_PHYSICS_H_
#define SITLNET_RUNNER_LOCAL_PHYSICS_H_

#include <memory>
#include <string>

#include "physics_side/physics_side.h"
#include "runner/recording_physics.h"
#include "runner/run_parts.h"
#include "runner/run_setup.h"

namespace sitlnet::runner {

class LocalPhysics final : public RunPhysics {
 public:
  // Creates trajectories.csv (throws Error naming it). `setup` must outlive this.
  LocalPhysics(RunSetup* setup, const RunOptions& options, const std::string& run_dir);
  coordinator::Connector& connector() override { return *connector_; }
  void Flush() override { recording_.Flush(); }
  std::optional<run_formats::ClosestApproach> closest_approach() const override {
    return recording_.closest_approach();
  }

 private:
  physics_side::PhysicsServerSimulator simulator_;
  RecordingPhysics recording_;
  std::unique_ptr<coordinator::Connector> connector_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_LOCAL_PHYSICS_H_

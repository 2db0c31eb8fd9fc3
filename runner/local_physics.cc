#include "runner/local_physics.h"

#include "runner/physics_options.h"

namespace sitlnet::runner {

LocalPhysics::LocalPhysics(RunSetup* setup, const RunOptions& options, const std::string& run_dir)
    : simulator_(setup->scenario(), &setup->physics_server(),
                 RobotLockstep(setup->scenario(), setup->lockstep())),
      recording_(&simulator_, physics::GeodeticFrame(setup->scenario().spec.geodetic_origin()),
                 run_dir + "/trajectories.csv", options.trajectory_period_ns),
      connector_(coordinator::MakeInProcessConnector("physics", coordinator::Role::kPhysics,
                                                     &recording_,
                                                     coordinator::Threading::kOwnThread)) {
  if (setup->shared_time() != nullptr) recording_.ShareTimeWith(setup->shared_time());
  recording_.SetLiveSink(options.live);
}

}  // namespace sitlnet::runner

// Benchmark knobs of the physics server, read from sitlnet run's environment.
#ifndef SITLNET_RUNNER_PHYSICS_OPTIONS_H_
#define SITLNET_RUNNER_PHYSICS_OPTIONS_H_

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::runner {

// Benchmark knobs (bench/scale, docs/performance.md), not scenario settings:
// SITLNET_PHYSICS_THREADS=N steps the robots on N threads (default 2) and
// SITLNET_PHYSICS_INTEGRATOR=euler|rk4 overrides the scenario's
// timing.physics_integrator (Euler trades RK4's accuracy, docs/physics.md, for about a
// third of its cost). Anything else is a one-line error.
physics::ServerOptions PhysicsOptionsFromEnvironment();

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_PHYSICS_OPTIONS_H_

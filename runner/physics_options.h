// Benchmark knobs of the physics server, read from sitlnet run's environment.
#ifndef SITLNET_RUNNER_PHYSICS_OPTIONS_H_
#define SITLNET_RUNNER_PHYSICS_OPTIONS_H_

#include <vector>

#include "clock/clock.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_side/physics_side.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// Benchmark knobs (bench/scale, docs/performance.md), not scenario settings:
// SITLNET_PHYSICS_THREADS=N steps the robots on N threads (default 2) and
// SITLNET_PHYSICS_INTEGRATOR=euler|rk4 overrides the scenario's
// timing.physics_integrator (Euler trades RK4's accuracy, docs/physics.md, for about a
// third of its cost). Anything else is a one-line error.
physics::ServerOptions PhysicsOptionsFromEnvironment();

// The physics server's options in a run of `scenario` (the environment's knobs included): its
// sockets in the scenario's ctl namespace, the autopilots paced by the frame gate in lockstep or
// by `wall_clock` (the run's timebase) in realtime. `robots`: those it simulates (empty: all).
physics::ServerOptions RunPhysicsOptions(const Scenario& scenario, bool lockstep,
                                         const clock::Timebase* wall_clock,
                                         const std::vector<int>& robots = {});

// Realtime pacing on a busy host: a normal-priority loop waits milliseconds for a core
// (docs/performance.md, "Realtime 64"). Asks SCHED_FIFO `priority` (0: none) for this process,
// before its physics and bridge threads exist, so that they inherit it; children (images,
// gnuplot) reset to normal scheduling. A refusal is one warning line on stderr from `program`.
void RequestRealtimeRunPriority(int priority, const char* program);

// The robots' lock-step with the physics (lockstep pacing), by the scenario's silent-robot
// timeout and policy.
physics_side::RobotLockstepOptions RobotLockstep(const Scenario& scenario, bool lockstep);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_PHYSICS_OPTIONS_H_

#include "runner/physics_options.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/common.h"
#include "nns/nns.h"

namespace sitlnet::runner {

physics::ServerOptions PhysicsOptionsFromEnvironment() {
  physics::ServerOptions options;
  if (const char* threads = std::getenv("SITLNET_PHYSICS_THREADS"); threads && *threads) {
    char* end = nullptr;
    const long value = std::strtol(threads, &end, 10);
    if (*end != '\0' || value < 1 || value > 64) {
      throw Error(std::string("SITLNET_PHYSICS_THREADS=\"") + threads + "\": want 1..64");
    }
    options.world.threads = static_cast<int>(value);
  }
  if (const char* integrator = std::getenv("SITLNET_PHYSICS_INTEGRATOR");
      integrator && *integrator) {
    const std::string name = integrator;
    if (name != "euler" && name != "rk4") {
      throw Error("SITLNET_PHYSICS_INTEGRATOR=\"" + name + "\": want euler or rk4");
    }
    options.world.integrator =
        name == "euler" ? physics::Integrator::kEuler : physics::Integrator::kRk4;
  }
  // SITLNET_PHYSICS_CULL_TILE_M=M: obstacle tiles of M metres; 0: no culling (docs/physics.md).
  if (const char* tile = std::getenv("SITLNET_PHYSICS_CULL_TILE_M"); tile && *tile) {
    char* end = nullptr;
    const double value = std::strtod(tile, &end);
    // 0 or at least a metre: a tile index is the position over the tile size, as an int64.
    if (*end != '\0' || !(value == 0 || (value >= 1 && value <= 1e6))) {
      throw Error(std::string("SITLNET_PHYSICS_CULL_TILE_M=\"") + tile +
                  "\": want 0 (no culling) or 1..1e6 m");
    }
    options.world.cull_obstacles = value > 0;
    if (value > 0) options.world.cull_tile_m = value;
  }
  return options;
}

physics::ServerOptions RunPhysicsOptions(const Scenario& scenario, bool lockstep,
                                         const clock::Timebase* wall_clock,
                                         const std::vector<int>& robots) {
  physics::ServerOptions options = PhysicsOptionsFromEnvironment();
  options.world.robots = robots;
  // Its sockets in the scenario's ctl namespace, where the robots' ctl0 links end: no one else
  // can bind their ports there (nns.h, CtlNetnsName).
  options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario.name));
  // The autopilots' pacing: in lockstep the frame gate (silent after the scenario's timeout),
  // in realtime the run's timebase (the coordinator begins it before iteration 0).
  if (lockstep) {
    options.periodic_states = false;  // one state per iteration, from the gate
    options.frame_gate_timeout_ns = scenario.spec.silent_robot_timeout_ms() * kNsPerMs;
  } else {
    options.autopilot_wall_clock = wall_clock;
  }
  return options;
}

void RequestRealtimeRunPriority(int priority, const char* program) {
  if (priority <= 0) return;
  if (const std::string refused = RequestRealtimePriority(priority); !refused.empty()) {
    std::fprintf(stderr, "%s: warning: %s\n", program, refused.c_str());
  }
}

physics_side::RobotLockstepOptions RobotLockstep(const Scenario& scenario, bool lockstep) {
  physics_side::RobotLockstepOptions robot_lockstep;
  robot_lockstep.enabled = lockstep;
  robot_lockstep.command_timeout_ns = scenario.spec.silent_robot_timeout_ms() * kNsPerMs;
  robot_lockstep.drop_silent =
      scenario.spec.on_silent_robot() == proto::Scenario::SILENT_ROBOT_DROP;
  return robot_lockstep;
}

}  // namespace sitlnet::runner

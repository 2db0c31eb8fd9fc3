#include <cstdio>

#include "physics_side/physics_side.h"

namespace sitlnet::physics_side {

void PosesFromWorld(const physics::World& world, proto::coord::Poses* poses) {
  for (const int robot : world.robots()) {
    const physics::RobotPose pose = world.Pose(robot);
    poses->add_position_m(pose.position_m.x);
    poses->add_position_m(pose.position_m.y);
    poses->add_position_m(pose.position_m.z);
    poses->add_orientation_wxyz(pose.orientation.w);
    poses->add_orientation_wxyz(pose.orientation.x);
    poses->add_orientation_wxyz(pose.orientation.y);
    poses->add_orientation_wxyz(pose.orientation.z);
    poses->add_velocity_m_s(pose.velocity_m_s.x);
    poses->add_velocity_m_s(pose.velocity_m_s.y);
    poses->add_velocity_m_s(pose.velocity_m_s.z);
  }
}

namespace {
// START must cover exactly the steps this connector takes. Its times come from another process,
// maybe another host (a fleet's central), so their difference may not fit an int64.
void CheckSpan(const proto::coord::Start& start, const physics::World& world, int steps) {
  TimeNs span_ns = 0;
  const bool overflows = __builtin_sub_overflow(start.end_ns(), start.start_ns(), &span_ns);
  if (overflows || span_ns != steps * world.step_ns()) {
    throw Error("physics connector: START of iteration " + std::to_string(start.iteration()) +
                " spans " + (overflows ? "more than an int64 of" : std::to_string(span_ns)) +
                " ns, expected " + std::to_string(steps) + " steps of " +
                std::to_string(world.step_ns()) + " ns");
  }
}
}  // namespace

proto::coord::Poses WorldSimulator::InitialPoses() {
  proto::coord::Poses poses;
  PosesFromWorld(world_, &poses);
  return poses;
}

void WorldSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                  IterationContext&) {
  CheckSpan(start, world_, steps_);
  world_.Advance(steps_);
  PosesFromWorld(world_, end->mutable_poses());
}

PhysicsServerSimulator::PhysicsServerSimulator(const Scenario& scenario,
                                               physics::PhysicsServer* server,
                                               RobotLockstepOptions lockstep)
    : server_(*server), steps_(scenario.physics_steps_per_iteration), lockstep_(lockstep) {
  for (const RobotPlan& robot : scenario.robots) robot_names_.push_back(robot.name);
}

proto::coord::Poses PhysicsServerSimulator::InitialPoses() {
  proto::coord::Poses poses;
  PosesFromWorld(server_.world(), &poses);
  return poses;
}

void PhysicsServerSimulator::ApplySilentRobotPolicy(const std::vector<int>& silent,
                                                    const std::string& what,
                                                    const std::string& with,
                                                    const proto::coord::Start& start) {
  if (silent.empty()) return;
  if (lockstep_.drop_silent) {
    for (int robot : silent) {
      server_.DropFromLockstep(robot);
      std::fprintf(stderr,
                   "sitlnet: robot '%s' did not answer %s of iteration %llu within %lld ms: "
                   "dropped from the run, motors cut\n",
                   robot_names_.at(robot).c_str(), what.c_str(),
                   static_cast<unsigned long long>(start.iteration()),
                   static_cast<long long>(lockstep_.command_timeout_ns / kNsPerMs));
    }
    return;
  }
  std::string names;
  for (int robot : silent) names += (names.empty() ? "'" : ", '") + robot_names_.at(robot) + "'";
  throw Error(std::string(silent.size() == 1 ? "robot " : "robots ") + names + " did not answer " +
              what + " of iteration " + std::to_string(start.iteration()) + " (virtual " +
              std::to_string(start.start_ns() / kNsPerMs) + " ms) " + with + " within " +
              std::to_string(lockstep_.command_timeout_ns / kNsPerMs) + " ms");
}

void PhysicsServerSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                          IterationContext& context) {
  CheckSpan(start, server_.world(), steps_);
  // ArduPilot robots exchange frames with the clock inside the iteration, and their radio
  // traffic of the iteration must all be in their TAPs before the network drains them: with
  // them, the network runs after physics (END opens its gate) instead of beside it.
  const bool gate_after_physics = server_.has_frame_gated_robots();
  if (lockstep_.enabled) {
    server_.SendStates();
    ApplySilentRobotPolicy(server_.CollectCommands(lockstep_.command_timeout_ns), "the state",
                           "with a command", start);
    if (!gate_after_physics) context.CommandsCollected();
  }
  server_.Advance(steps_);
  if (lockstep_.enabled) {
    // Each autopilot named with its own protocol's words (one Error names the robots of one
    // protocol; the server lists them protocol by protocol).
    const std::vector<physics::SilentAutopilot> silent = server_.TakeSilentAutopilots();
    for (size_t begin = 0, end; begin < silent.size(); begin = end) {
      std::vector<int> robots;
      for (end = begin; end < silent.size() && silent[end].unanswered == silent[begin].unanswered;
           ++end) {
        robots.push_back(silent[end].robot);
      }
      ApplySilentRobotPolicy(robots, silent[begin].unanswered, silent[begin].expected, start);
    }
  }
  PosesFromWorld(server_.world(), end->mutable_poses());
}

}  // namespace sitlnet::physics_side

// The robot-facing lock-step over real UDP: robots (threads with the physics
// client library, on 127.79.x addresses, apart from physics_mujoco's 127.77.x)
// answer each state with a command; the network iteration starts only after
// every command of that iteration arrived; a robot that stops answering
// stops the run with its name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <thread>

#include "coordinator/coordinator.h"
#include "physics_mujoco/client/physics_client.h"
#include "physics_side/physics_side.h"

namespace sitlnet::physics_side {
namespace {

// These tests drive the coordinator directly.
using namespace coordinator;  // NOLINT(google-build-using-namespace)

uint16_t TestPort() { return static_cast<uint16_t>(40000 + 2 * (getpid() % 10000)); }

Scenario TwoRobots() {
  const std::string text =
      "name: \"lsr\"\n"
      "robot { name: \"a\" position_m { z: 5 } state_rate_hz: 1 }\n"
      "robot { name: \"b\" position_m { x: 3 z: 5 } state_rate_hz: 1 }\n"
      "addresses { ctl_subnet: \"127.79.0.0/16\" physics_port: " +
      std::to_string(TestPort()) +
      " }\n"
      "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: 10000 "
      "duration_ms: 300 pacing: PACING_LOCKSTEP }\n";
  return LoadScenarioText(text, "lsr.textproto");
}

// A robot: joins with a first command, then answers every state with a
// command for that state's step, until `stop` or after `answers` answers.
void Robot(int index, int answers, const std::atomic<bool>* stop) {
  physics_client::PhysicsClient client(
      "127.79.0." + std::to_string(4 * index + 1) + ":" + std::to_string(TestPort()),
      "127.79.0." + std::to_string(4 * index + 2));
  client.SendRotorSpeeds({100, 100, 100, 100});
  proto::RobotState state;
  for (int n = 0; n < answers && !stop->load();) {
    if (!client.Receive(&state, 100)) continue;
    client.SendRotorSpeeds({100, 100, 100, 100}, state.step());
    ++n;
  }
}

// Records the last iteration whose commands were all collected.
class GateRecorder final : public Simulator, private IterationContext {
 public:
  GateRecorder(Simulator* inner, std::atomic<int64_t>* collected)
      : inner_(*inner), collected_(*collected) {}
  proto::coord::Poses InitialPoses() override { return inner_.InitialPoses(); }
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override {
    outer_ = &context;
    iteration_ = static_cast<int64_t>(start.iteration());
    inner_.RunIteration(start, end, *this);
  }

 private:
  void CommandsCollected() override {
    collected_.store(iteration_);
    outer_->CommandsCollected();
  }
  Simulator& inner_;
  std::atomic<int64_t>& collected_;
  IterationContext* outer_ = nullptr;
  int64_t iteration_ = -1;
};

class GateChecker final : public Simulator {
 public:
  explicit GateChecker(std::atomic<int64_t>* collected) : collected_(*collected) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    IterationContext&) override {
    if (collected_.load() != static_cast<int64_t>(start.iteration())) ++violations;
    ++iterations;
  }
  int violations = 0;
  int iterations = 0;

 private:
  std::atomic<int64_t>& collected_;
};

struct Fixture {
  Scenario scenario = TwoRobots();
  physics::PhysicsServer server{scenario};
  std::atomic<int64_t> collected{-1};
  std::atomic<bool> stop{false};
};

// Handles packets until both robots joined (their first command arrived).
void WaitForJoin(physics::PhysicsServer* server) {
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (
      (server->counters(0).commands_accepted == 0 || server->counters(1).commands_accepted == 0) &&
      MonotonicNowNs() < deadline) {
    server->CollectCommands(10 * kNsPerMs);  // Polls the sockets, bounded.
  }
}

TEST(RobotLockstep, NetworkStartsOnlyAfterEveryRobotsCommand) {
  Fixture f;
  std::thread a(Robot, 0, 1 << 30, &f.stop);
  std::thread b(Robot, 1, 1 << 30, &f.stop);
  WaitForJoin(&f.server);
  PhysicsServerSimulator physics_sim(f.scenario, &f.server, {true, 2 * kNsPerS});
  GateRecorder recorder(&physics_sim, &f.collected);
  GateChecker network_sim(&f.collected);
  auto physics =
      MakeInProcessConnector("physics", Role::kPhysics, &recorder, Threading::kOwnThread);
  auto network =
      MakeInProcessConnector("network", Role::kNetwork, &network_sim, Threading::kCallerThread);
  CoordinatorOptions options = OptionsFromScenario(f.scenario);
  options.lockstep_robots = true;
  const RunResult result = RunCoordinator(*physics, *network, options);
  f.stop = true;
  a.join();
  b.join();
  EXPECT_EQ(result.iterations_done, 30);
  EXPECT_EQ(network_sim.iterations, 30);
  EXPECT_EQ(network_sim.violations, 0);
  // Every iteration's state was answered: at least one command per iteration
  // per robot besides the joining one.
  EXPECT_GE(f.server.counters(0).commands_accepted, 31u);
  EXPECT_GE(f.server.counters(1).commands_accepted, 31u);
}

// Robot a answers every state, robot b those of iterations 0..4 only; runs the
// coordinator with `lockstep` (throws what RunCoordinator throws).
RunResult RunWithRobotBSilentAfterFive(Fixture& f, const RobotLockstepOptions& lockstep) {
  std::thread a(Robot, 0, 1 << 30, &f.stop);
  std::thread b(Robot, 1, 5, &f.stop);
  struct JoinAtExit {
    Fixture& f;
    std::thread& a;
    std::thread& b;
    ~JoinAtExit() {
      f.stop = true;
      a.join();
      b.join();
    }
  } join{f, a, b};
  WaitForJoin(&f.server);
  PhysicsServerSimulator physics_sim(f.scenario, &f.server, lockstep);
  GateChecker network_sim(&f.collected);
  auto physics =
      MakeInProcessConnector("physics", Role::kPhysics, &physics_sim, Threading::kOwnThread);
  auto network =
      MakeInProcessConnector("network", Role::kNetwork, &network_sim, Threading::kCallerThread);
  CoordinatorOptions options = OptionsFromScenario(f.scenario);
  options.lockstep_robots = true;
  return RunCoordinator(*physics, *network, options);
}

TEST(RobotLockstep, ARobotThatStopsAnsweringStopsTheRunWithItsName) {
  Fixture f;
  try {
    RunWithRobotBSilentAfterFive(f, {true, 200 * kNsPerMs});
    ADD_FAILURE() << "the run went on without robot b";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "physics connector 'physics' failed in iteration 5: robot 'b' did not answer "
                 "the state of iteration 5 (virtual 50 ms) with a command within 200 ms");
  }
}

TEST(RobotLockstep, ASilentRobotCanBeDroppedWithItsMotorsCut) {
  Fixture f;
  RobotLockstepOptions lockstep{true, 200 * kNsPerMs};
  lockstep.drop_silent = true;
  const RunResult result = RunWithRobotBSilentAfterFive(f, lockstep);
  EXPECT_EQ(result.iterations_done, 30);  // the run went on without b
  EXPECT_EQ(f.server.world().rotor_target(1), (physics::RotorSpeeds{0, 0, 0, 0}));
  EXPECT_EQ(f.server.counters(1).failsafe_cuts, 1u);
  EXPECT_EQ(f.server.world().rotor_target(0), (physics::RotorSpeeds{100, 100, 100, 100}));
}

}  // namespace
}  // namespace sitlnet::physics_side

// The paper's correctness method (DANCERS Sec. V-C) for the physics side:
// with network traffic that does not influence control, the trajectories of
// a co-simulated run (physics behind a Unix socket, the 802.11 medium
// carrying broadcast traffic) are bit-identical to physics run alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <thread>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"
#include "physics_side/physics_side.h"

namespace sitlnet::physics_side {
namespace {

// These tests drive the coordinator directly.
using namespace coordinator;   // NOLINT(google-build-using-namespace)
using namespace network_side;  // NOLINT(google-build-using-namespace)

constexpr int kRobots = 4;
constexpr int64_t kIterations = 200;  // 2 s of flight, 2000 physics steps.

Scenario TestScenario() {
  std::string text = "name: \"pcorr\"\n";
  for (int i = 0; i < kRobots; ++i) {
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(4 * i) + " y: 0 z: 5 } }\n";
  }
  text +=
      "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: 1000 "
      "duration_ms: 2000 pacing: PACING_LOCKSTEP }\n";
  return LoadScenarioText(text, "pcorr.textproto");
}

// Fixed, different rotor speeds per robot: climbing, tilting, yawing flight.
void SetRotors(physics::World* world) {
  for (int i = 0; i < kRobots; ++i) {
    const proto::Airframe& a = world->airframe(i);
    const double hover = std::sqrt(a.mass_kg() * 9.81 / (4 * a.thrust_coefficient()));
    const double d = 0.004 * (i + 1);
    world->SetRotorSpeeds(i, {hover * (1 + d), hover * (1 + 0.5 * d), hover, hover * (1 + d)});
  }
}

using Trajectory = std::vector<double>;  // Per iteration: x, y, z, qw, qx, qy, qz per robot.

void Append(const proto::coord::Poses& poses, Trajectory* out) {
  for (int i = 0; i < kRobots; ++i) {
    for (int c = 0; c < 3; ++c) out->push_back(poses.position_m(3 * i + c));
    for (int c = 0; c < 4; ++c) out->push_back(poses.orientation_wxyz(4 * i + c));
  }
}

// Records the poses each End carried to the coordinator.
class RecordingWorld final : public Simulator {
 public:
  RecordingWorld(const Scenario& s, physics::World* world) : inner_(s, world) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override {
    inner_.RunIteration(start, end, context);
    Append(end->poses(), &trajectory_);
  }
  proto::coord::Poses InitialPoses() override { return inner_.InitialPoses(); }
  Trajectory trajectory_;

 private:
  WorldSimulator inner_;
};

// The network side sees the poses that crossed the socket; it records them
// so the test also checks what travelled, not only what physics computed.
class RecordingMedium final : public Simulator {
 public:
  RecordingMedium(const Scenario& s, FrameSource* traffic) : inner_(s, traffic) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override {
    if (start.iteration() > 0) Append(start.poses(), &received_);
    inner_.RunIteration(start, end, context);
  }
  Trajectory received_;
  uint64_t deliveries() const { return inner_.delivery_count(); }

 private:
  MediumSimulator inner_;
};

TEST(PhysicsCorrectness, CoSimulatedTrajectoriesAreBitIdenticalToPhysicsAlone) {
  const Scenario scenario = TestScenario();
  const uint64_t hash = ScenarioHash(scenario);

  // Co-simulation: physics as a socket connector on its own thread.
  physics::World cosim_world(scenario);
  SetRotors(&cosim_world);
  RecordingWorld physics_sim(scenario, &cosim_world);
  const std::string path = "/tmp/sitlnet-pcorr-" + std::to_string(getpid()) + ".sock";
  Listener listener(ParseEndpoint("unix:" + path));
  std::string connector_error;
  std::thread connector([&] {
    try {
      Channel channel(Connect(listener.endpoint(), MonotonicNowNs() + 5 * kNsPerS));
      ServeCoordinator(channel, physics_sim, {"mujoco", Role::kPhysics, hash, {}}, 5 * kNsPerS);
    } catch (const Error& e) {
      connector_error = e.what();
    }
  });
  PeriodicBroadcast traffic(kRobots, 100 * kNsPerMs, 200);
  RecordingMedium medium(scenario, &traffic);
  auto network =
      MakeInProcessConnector("medium", Role::kNetwork, &medium, Threading::kCallerThread);
  WaitLimits limits;
  limits.timeout_ns = 10 * kNsPerS;
  limits.deadline_ns = MonotonicNowNs() + limits.timeout_ns;
  auto physics = AcceptConnector(Channel(listener.Accept(limits.deadline_ns)),
                                 {hash, scenario.iteration_ns, false, std::nullopt, {}}, limits);
  const CoordinatorOptions options = OptionsFromScenario(scenario);
  ASSERT_EQ(options.iterations, kIterations);
  EXPECT_EQ(RunCoordinator(*physics, *network, options).iterations_done, kIterations);
  physics.reset();
  connector.join();
  ASSERT_EQ(connector_error, "");
  EXPECT_GT(medium.deliveries(), 0u);  // Traffic did flow.

  // Physics alone, the same steps, no coordinator.
  physics::World alone_world(scenario);
  SetRotors(&alone_world);
  Trajectory alone;
  for (int64_t k = 0; k < kIterations; ++k) {
    alone_world.Advance(scenario.physics_steps_per_iteration);
    proto::coord::Poses poses;
    PosesFromWorld(alone_world, &poses);
    Append(poses, &alone);
  }

  ASSERT_EQ(physics_sim.trajectory_.size(), alone.size());
  // The robots really moved (a trivial trajectory would prove nothing).
  EXPECT_GT(std::abs(alone[alone.size() - 7 + 2] - 5.0), 0.05);  // Last robot's z.
  EXPECT_EQ(
      std::memcmp(physics_sim.trajectory_.data(), alone.data(), alone.size() * sizeof(double)), 0);
  // What reached the network at START k+1 is physics' End k, bit for bit.
  const Trajectory expected_received(alone.begin(),
                                     alone.end() - static_cast<std::ptrdiff_t>(7 * kRobots));
  ASSERT_EQ(medium.received_.size(), expected_received.size());
  for (size_t i = 0; i < expected_received.size(); ++i) {
    ASSERT_EQ(std::memcmp(&medium.received_[i], &expected_received[i], sizeof(double)), 0)
        << "value " << i;
  }
}

// Reproducibility (issue 6, item 6) with both real simulators: two lockstep
// runs of MuJoCo + the medium, both behind sockets, give identical
// trajectories and identical medium deliveries; another seed changes the
// medium's random draws (and only those: physics does not depend on them).
struct RunOutputs {
  Trajectory trajectory;
  std::vector<mac::Delivery> deliveries;
};

RunOutputs RunBothOverSockets(const Scenario& scenario) {
  const uint64_t hash = ScenarioHash(scenario);
  physics::World world(scenario);
  SetRotors(&world);
  RecordingWorld physics_sim(scenario, &world);
  // Saturating traffic so that backoff draws (the seeded part) matter.
  PeriodicBroadcast traffic(kRobots, 2 * kNsPerMs, 1400);
  MediumSimulator medium(scenario, &traffic);
  medium.set_record(true);
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  std::string errors;
  auto serve = [&](Simulator* sim, ConnectorIdentity id) {
    try {
      Channel channel(Connect(listener.endpoint(), MonotonicNowNs() + 5 * kNsPerS));
      ServeCoordinator(channel, *sim, id, 5 * kNsPerS);
    } catch (const Error& e) {
      errors += e.what();
    }
  };
  std::thread phys(serve, &physics_sim, ConnectorIdentity{"mujoco", Role::kPhysics, hash, {}});
  std::thread net(serve, &medium, ConnectorIdentity{"medium", Role::kNetwork, hash, {}});
  WaitLimits limits;
  limits.timeout_ns = 10 * kNsPerS;
  limits.deadline_ns = MonotonicNowNs() + limits.timeout_ns;
  AcceptedConnectors c =
      AcceptConnectors(listener, {hash, scenario.iteration_ns, false, std::nullopt, {}}, limits);
  RunCoordinator(*c.physics, *c.network, OptionsFromScenario(scenario));
  c = {};
  phys.join();
  net.join();
  EXPECT_EQ(errors, "");
  return {physics_sim.trajectory_, medium.deliveries()};
}

Scenario WithSeed(uint64_t seed) {
  std::string text = "name: \"prepro\"\n";
  for (int i = 0; i < kRobots; ++i) {
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(4 * i) + " y: 0 z: 5 } }\n";
  }
  text += "radio { rate_mbps: 6 }\n";
  text +=
      "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: 1000 "
      "duration_ms: 500 pacing: PACING_LOCKSTEP seed: " +
      std::to_string(seed) + " }\n";
  return LoadScenarioText(text, "prepro.textproto");
}

TEST(Reproducibility, TwoLockstepRunsGiveIdenticalTrajectoriesAndDeliveries) {
  const RunOutputs first = RunBothOverSockets(WithSeed(7));
  const RunOutputs second = RunBothOverSockets(WithSeed(7));
  ASSERT_FALSE(first.trajectory.empty());
  ASSERT_GT(first.deliveries.size(), 10u);
  EXPECT_EQ(std::memcmp(first.trajectory.data(), second.trajectory.data(),
                        first.trajectory.size() * sizeof(double)),
            0);
  EXPECT_TRUE(first.deliveries == second.deliveries);
  const RunOutputs other = RunBothOverSockets(WithSeed(8));
  EXPECT_FALSE(first.deliveries == other.deliveries) << "seed 8 gave seed 7's deliveries";
  EXPECT_EQ(std::memcmp(first.trajectory.data(), other.trajectory.data(),
                        first.trajectory.size() * sizeof(double)),
            0);
}

}  // namespace
}  // namespace sitlnet::physics_side

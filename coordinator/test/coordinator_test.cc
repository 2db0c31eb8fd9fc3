// The run loop over in-process and socket connectors, with synthetic
// simulators whose poses are exact functions of virtual time; realtime
// pacing with an injected clock; the lockstep-robots gate.
#include "coordinator/coordinator.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>

#include "coordinator/synthetic.h"
#include "coordinator/test/fake_clock.h"
#include "coordinator/test/test_connectors.h"

namespace sitlnet::coordinator {
namespace {

using namespace test_support;  // NOLINT: test helpers.

void ExpectPosesDelayedByOneIteration(const SyntheticNetwork& network, int64_t iterations) {
  ASSERT_EQ(network.first_robot_x_m().size(), static_cast<size_t>(iterations));
  for (int64_t k = 0; k < iterations; ++k) {
    proto::coord::Poses expected;
    SyntheticPhysics::PosesAt(3, k * kDelta, &expected);
    EXPECT_EQ(network.start_times_ns()[k], k * kDelta);
    EXPECT_EQ(network.first_robot_x_m()[k], expected.position_m(0)) << "iteration " << k;
  }
}

TEST(Coordinator, InProcessPassesPhysicsPosesToTheNextNetworkStart) {
  SyntheticPhysics physics_sim(Robots(3));
  SyntheticNetwork network_sim(Robots(3));
  auto physics =
      MakeInProcessConnector("phys0", Role::kPhysics, &physics_sim, Threading::kOwnThread);
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kCallerThread);
  MetricsCollector metrics;
  CoordinatorOptions options = Lockstep(50);
  options.metrics = &metrics;
  const RunResult result = RunCoordinator(*physics, *network, options);
  EXPECT_EQ(result.iterations_done, 50);
  EXPECT_FALSE(result.interrupted);
  ExpectPosesDelayedByOneIteration(network_sim, 50);
  ASSERT_EQ(metrics.rows().size(), 50u);
  for (const IterationMetrics& m : metrics.rows()) {
    EXPECT_EQ(m.t_overhead_ns, m.t_total_ns - std::max(m.t_phy_ns, m.t_net_ns));
    EXPECT_EQ(m.lag_ns, 0);
  }
}

// Runs a simulator as a connector over `endpoint` on its own thread.
void RunOverSockets(const std::string& where, bool lockstep_robots = false) {
  Listener listener(ParseEndpoint(where));
  SyntheticPhysics physics_sim(Robots(3));
  SyntheticNetwork network_sim(Robots(3));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
  AcceptedConnectors connectors = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  ASSERT_TRUE(connectors.physics && connectors.network);
  EXPECT_EQ(connectors.physics->Describe(), "physics connector 'phys0'");
  CoordinatorOptions options = Lockstep(40);
  options.lockstep_robots = lockstep_robots;
  const RunResult result = RunCoordinator(*connectors.physics, *connectors.network, options);
  EXPECT_EQ(result.iterations_done, 40);
  connectors = {};  // Closes the sockets after Stop.
  phys.Join();
  net.Join();
  EXPECT_EQ(phys.error(), "");
  EXPECT_EQ(phys.stop_reason(), "run complete");
  ExpectPosesDelayedByOneIteration(network_sim, 40);
}

// A physics connector that never reports CommandsCollected (no robots in
// lock-step): its END opens the gate, the run goes on (network after physics).
TEST(Coordinator, LockstepRobotsGateOpensOnEndWithoutCommandsCollected) {
  RunOverSockets("unix:/tmp/sitlnet-coord-gate-" + std::to_string(getpid()) + ".sock",
                 /*lockstep_robots=*/true);
}

TEST(Coordinator, RemoteOverUnixSocket) {
  RunOverSockets("unix:/tmp/sitlnet-coord-" + std::to_string(getpid()) + ".sock");
}

TEST(Coordinator, RemoteOverTcpLoopback) { RunOverSockets("127.0.0.1:0"); }

TEST(Coordinator, RealtimePacingEndsEachIterationAtItsDeadline) {
  FakeClock clock;
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  auto physics =
      MakeInProcessConnector("phys0", Role::kPhysics, &physics_sim, Threading::kCallerThread);
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kCallerThread);
  CoordinatorOptions options = Lockstep(5);
  options.pacing = Pacing::kRealtime;
  options.realtime_factor = 2.0;
  options.wall_clock = &clock;
  const TimeNs origin = clock.NowNs();
  clock.set_advance_per_read_ns(kNsPerMs);  // Every clock read "costs" 1 ms of work.
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  MetricsCollector metrics;
  options.metrics = &metrics;
  RunCoordinator(*physics, *network, options);
  // Factor 2: iteration k may end at origin + (k+1)·5 ms; the run reads its
  // origin first, before any simulated work, so it equals `origin`.
  ASSERT_EQ(clock.sleeps().size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(clock.sleeps()[k], origin + (k + 1) * 5 * kNsPerMs);
  }
  for (const IterationMetrics& m : metrics.rows()) EXPECT_EQ(m.lag_ns, 0);
  EXPECT_TRUE(warnings.empty());
}

TEST(Coordinator, RealtimeLagIsMeasuredAndWarnedWithNumbers) {
  FakeClock clock;
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  auto physics =
      MakeInProcessConnector("phys0", Role::kPhysics, &physics_sim, Threading::kCallerThread);
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kCallerThread);
  CoordinatorOptions options = Lockstep(3);
  options.pacing = Pacing::kRealtime;
  options.wall_clock = &clock;
  clock.set_advance_per_read_ns(12 * kNsPerMs);  // Each read 12 ms later: too slow for 10 ms.
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  MetricsCollector metrics;
  options.metrics = &metrics;
  RunCoordinator(*physics, *network, options);
  // Reads: origin o; iteration k reads t0 = o + (2k+1)·12, t1 = o + (2k+2)·12 ms;
  // deadline o + (k+1)·10 ms; lag = t1 - deadline = 14k + 14 ms.
  ASSERT_EQ(metrics.rows().size(), 3u);
  EXPECT_EQ(metrics.rows()[0].lag_ns, 14 * kNsPerMs);
  EXPECT_EQ(metrics.rows()[2].lag_ns, 42 * kNsPerMs);
  ASSERT_EQ(warnings.size(), 1u);  // Rate-limited: 3 late iterations within 1 s of wall.
  EXPECT_NE(warnings[0].find("behind real time by 14.0 ms at iteration 0"), std::string::npos)
      << warnings[0];
}

// Lockstep robots: the network may start only after physics collected the
// commands, so frames written before each command are in the TAPs.
class OrderedPhysics final : public Simulator {
 public:
  explicit OrderedPhysics(std::atomic<int64_t>* collected) : collected_(collected) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    IterationContext& context) override {
    collected_->store(static_cast<int64_t>(start.iteration()));
    context.CommandsCollected();
  }

 private:
  std::atomic<int64_t>* collected_;
};

class CheckingNetwork final : public Simulator {
 public:
  explicit CheckingNetwork(std::atomic<int64_t>* collected) : collected_(collected) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    IterationContext&) override {
    if (collected_->load() != static_cast<int64_t>(start.iteration())) ++violations_;
  }
  int violations_ = 0;

 private:
  std::atomic<int64_t>* collected_;
};

TEST(Coordinator, LockstepRobotsStartsNetworkAfterCommandsCollected) {
  std::atomic<int64_t> collected{-1};
  OrderedPhysics physics_sim(&collected);
  CheckingNetwork network_sim(&collected);
  Listener listener(ParseEndpoint("unix:/tmp/sitlnet-coord-ls-" + std::to_string(getpid())));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kOwnThread);
  HandshakeExpectation expect = Expect();
  expect.lockstep_robots = true;
  UniqueFd fd = listener.Accept(MonotonicNowNs() + 5 * kNsPerS);
  auto physics = AcceptConnector(Channel(std::move(fd)), expect, Within(5 * kNsPerS));
  CoordinatorOptions options = Lockstep(200);
  options.lockstep_robots = true;
  EXPECT_EQ(RunCoordinator(*physics, *network, options).iterations_done, 200);
  EXPECT_EQ(network_sim.violations_, 0);
}

}  // namespace
}  // namespace sitlnet::coordinator

// The run loop over in-process and socket connectors, with synthetic
// simulators whose poses are exact functions of virtual time.
#include "coordinator/coordinator.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <future>
#include <thread>

#include "coordinator/synthetic.h"
#include "coordinator/test/fake_clock.h"

namespace sitlnet::coordinator {
namespace {

constexpr TimeNs kDelta = 10 * kNsPerMs;
constexpr uint64_t kHash = 0x5117'0e70'0000'0001ull;

SyntheticOptions Robots(int robots) {
  SyntheticOptions options;
  options.robots = robots;
  options.step_ns = kDelta;
  return options;
}

CoordinatorOptions Lockstep(int64_t iterations) {
  CoordinatorOptions options;
  options.iteration_ns = kDelta;
  options.iterations = iterations;
  options.pacing = Pacing::kLockstep;
  options.answer_timeout_ns = 5 * kNsPerS;
  return options;
}

// The network at iteration k must see the poses physics reported at kΔ.
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
class ConnectorThread {
 public:
  ConnectorThread(Endpoint endpoint, Simulator* simulator, ConnectorIdentity identity)
      : thread_([=, this] {
          try {
            Channel channel(Connect(endpoint, MonotonicNowNs() + 5 * kNsPerS));
            stop_reason_ = ServeCoordinator(channel, *simulator, identity, 5 * kNsPerS);
          } catch (const Error& e) {
            error_ = e.what();
          }
        }) {}
  ~ConnectorThread() { Join(); }
  void Join() {
    if (thread_.joinable()) thread_.join();
  }
  const std::string& error() const { return error_; }
  const std::string& stop_reason() const { return stop_reason_; }

 private:
  std::string error_;
  std::string stop_reason_;
  std::thread thread_;
};

HandshakeExpectation Expect() {
  HandshakeExpectation expect;
  expect.scenario_hash = kHash;
  expect.iteration_ns = kDelta;
  return expect;
}

WaitLimits Within(TimeNs timeout_ns) {
  WaitLimits limits;
  limits.timeout_ns = timeout_ns;
  limits.deadline_ns = MonotonicNowNs() + timeout_ns;
  return limits;
}

void RunOverSockets(const std::string& where) {
  Listener listener(ParseEndpoint(where));
  SyntheticPhysics physics_sim(Robots(3));
  SyntheticNetwork network_sim(Robots(3));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  AcceptedConnectors connectors = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  ASSERT_TRUE(connectors.physics && connectors.network);
  EXPECT_EQ(connectors.physics->Describe(), "physics connector 'phys0'");
  const RunResult result = RunCoordinator(*connectors.physics, *connectors.network, Lockstep(40));
  EXPECT_EQ(result.iterations_done, 40);
  connectors = {};  // Closes the sockets after Stop.
  phys.Join();
  net.Join();
  EXPECT_EQ(phys.error(), "");
  EXPECT_EQ(phys.stop_reason(), "run complete");
  ExpectPosesDelayedByOneIteration(network_sim, 40);
}

TEST(Coordinator, RemoteOverUnixSocket) {
  RunOverSockets("unix:/tmp/sitlnet-coord-" + std::to_string(getpid()) + ".sock");
}

TEST(Coordinator, RemoteOverTcpLoopback) { RunOverSockets("127.0.0.1:0"); }

TEST(Coordinator, HandshakeRefusesAnotherScenarioAndSaysSoToBothSides) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash + 1});
  const std::string expected =
      "physics connector 'phys0' loaded a different scenario: hash 0x51170e7000000002, the "
      "coordinator's is 0x51170e7000000001";
  try {
    AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), expected);
  }
  phys.Join();
  EXPECT_EQ(phys.error(), "the coordinator refused: " + expected);
}

TEST(Coordinator, StrayConnectionsAreIgnoredAndTheConnectorsStillAccepted) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  // Garbage first (a bad frame), then a client that closes at once.
  Fd garbage = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  ASSERT_EQ(write(garbage.get(), "GET / HTTP/1.0\r\n\r\n", 18), 18);
  Fd closer = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  closer.Reset();
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  ASSERT_TRUE(c.physics && c.network);
  EXPECT_EQ(RunCoordinator(*c.physics, *c.network, Lockstep(5)).iterations_done, 5);
}

TEST(Coordinator, MissingConnectorTimesOutNamingTheRole) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  try {
    AcceptConnectors(listener, Expect(), Within(200 * kNsPerMs));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "no physics connector connected to " +
                                         listener.endpoint().ToString() + " within 200 ms");
  }
}

// A physics simulator that never finishes iteration `stuck_at` until released.
class StuckPhysics final : public Simulator {
 public:
  StuckPhysics(int stuck_at, std::shared_future<void> release)
      : stuck_at_(stuck_at), release_(std::move(release)) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext&) override {
    if (start.iteration() == static_cast<uint64_t>(stuck_at_)) release_.wait();
  }

 private:
  int stuck_at_;
  std::shared_future<void> release_;
};

TEST(Coordinator, TimeoutNamesTheStuckConnectorAndIteration) {
  Listener listener(ParseEndpoint("unix:/tmp/sitlnet-coord-stuck-" + std::to_string(getpid())));
  std::promise<void> release;
  StuckPhysics physics_sim(3, release.get_future().share());
  SyntheticNetwork network_sim(Robots(0));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  CoordinatorOptions options = Lockstep(10);
  options.answer_timeout_ns = 300 * kNsPerMs;
  try {
    RunCoordinator(*c.physics, *c.network, options);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "physics connector 'phys0' did not answer START of iteration 3 with END within "
                 "300 ms");
  }
  release.set_value();
  c = {};
  phys.Join();
  net.Join();
  EXPECT_EQ(net.stop_reason(), "coordinator failed");  // The healthy one was told to stop.
}

TEST(Coordinator, CrashedConnectorProcessIsReportedByName) {
  const std::string path = "/tmp/sitlnet-coord-crash-" + std::to_string(getpid());
  Listener listener(ParseEndpoint("unix:" + path));
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // A network connector process that dies (no goodbye) in iteration 2.
    class Crashing final : public Simulator {
      void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                        IterationContext&) override {
        if (start.iteration() == 2) _exit(3);
      }
    } crashing;
    try {
      Channel channel(Connect(listener.endpoint(), MonotonicNowNs() + 5 * kNsPerS));
      ServeCoordinator(channel, crashing, {"net0", Role::kNetwork, kHash}, 5 * kNsPerS);
    } catch (...) {
    }
    _exit(0);
  }
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  try {
    RunCoordinator(*c.physics, *c.network, Lockstep(10));
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "network connector 'net0' failed during iteration 2: peer closed the connection "
                 "(connector crashed or exited)");
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_EQ(WEXITSTATUS(status), 3);
}

TEST(Coordinator, SimulatorErrorIsForwardedWithTheConnectorName) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticPhysics physics_sim(Robots(2));
  SyntheticNetwork network_sim(Robots(5));  // Expects 5 robots, gets 2: throws.
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  try {
    RunCoordinator(*c.physics, *c.network, Lockstep(10));
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "network connector 'net0' reported an error in iteration 0: synthetic network: "
                 "START of iteration 0 carries 2 positions, expected 5");
  }
}

// Requests a stop (as SIGINT would) from inside iteration `at`.
class InterruptingPhysics final : public Simulator {
 public:
  InterruptingPhysics(int at, StopSignal* stop) : at_(at), stop_(stop) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    IterationContext&) override {
    if (start.iteration() == static_cast<uint64_t>(at_)) raise(SIGINT);
  }

 private:
  int at_;
  StopSignal* stop_;
};

TEST(Coordinator, SigintStopsInOrderAndFlushesWholeRows) {
  StopSignal stop;
  const std::string csv = "/tmp/sitlnet-coord-sigint-" + std::to_string(getpid()) + ".csv";
  Listener listener(ParseEndpoint("unix:" + csv + ".sock"));
  InterruptingPhysics physics_sim(7, &stop);
  SyntheticNetwork network_sim(Robots(0));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  RunResult result;
  {
    MetricsCsvWriter writer(csv, /*rows_per_flush=*/1000);
    CoordinatorOptions options = Lockstep(1000);
    options.interrupt_fd = stop.fd();
    options.metrics_csv = &writer;
    result = RunCoordinator(*c.physics, *c.network, options);
    // Flushed by the run itself, before the writer goes away.
    FILE* f = fopen(csv.c_str(), "r");
    ASSERT_NE(f, nullptr);
    int lines = 0;
    for (int ch; (ch = fgetc(f)) != EOF;) lines += ch == '\n';
    fclose(f);
    EXPECT_EQ(lines, 1 + result.iterations_done);
  }
  EXPECT_TRUE(result.interrupted);
  EXPECT_EQ(stop.signal_number(), SIGINT);
  // Iteration 7 was running when the signal came: 7 or 8 complete rows.
  EXPECT_GE(result.iterations_done, 7);
  EXPECT_LE(result.iterations_done, 8);
  c = {};
  phys.Join();
  net.Join();
  EXPECT_EQ(phys.error(), "");
  EXPECT_NE(phys.stop_reason().find("interrupted"), std::string::npos) << phys.stop_reason();
  unlink(csv.c_str());
}

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
  options.clock = &clock;
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
  options.clock = &clock;
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
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash});
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kOwnThread);
  HandshakeExpectation expect = Expect();
  expect.lockstep_robots = true;
  Fd fd = listener.Accept(MonotonicNowNs() + 5 * kNsPerS);
  auto physics = AcceptConnector(Channel(std::move(fd)), expect, Within(5 * kNsPerS));
  CoordinatorOptions options = Lockstep(200);
  options.lockstep_robots = true;
  EXPECT_EQ(RunCoordinator(*physics, *network, options).iterations_done, 200);
  EXPECT_EQ(network_sim.violations_, 0);
}

}  // namespace
}  // namespace sitlnet::coordinator

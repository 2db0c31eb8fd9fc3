// A run that goes wrong: a stuck connector, a crashed connector process, a
// simulator error, SIGINT. Each is reported by name, nothing hangs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <future>

#include "coordinator/coordinator.h"
#include "coordinator/test/test_connectors.h"

namespace sitlnet::coordinator {
namespace {

using namespace test_support;  // NOLINT: test helpers.

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
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
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
      ServeCoordinator(channel, crashing, {"net0", Role::kNetwork, kHash, {}}, 5 * kNsPerS);
    } catch (...) {
    }
    _exit(0);
  }
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
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
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
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
  InterruptingPhysics(int at, StopSignal* stop, int signal_number = SIGINT)
      : at_(at), stop_(stop), signal_number_(signal_number) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    IterationContext&) override {
    if (start.iteration() == static_cast<uint64_t>(at_)) raise(signal_number_);
  }

 private:
  int at_;
  StopSignal* stop_;
  int signal_number_;
};

TEST(Coordinator, SigintStopsInOrderAndFlushesWholeRows) {
  StopSignal stop;
  const std::string csv = "/tmp/sitlnet-coord-sigint-" + std::to_string(getpid()) + ".csv";
  Listener listener(ParseEndpoint("unix:" + csv + ".sock"));
  InterruptingPhysics physics_sim(7, &stop);
  SyntheticNetwork network_sim(Robots(0));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
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

TEST(Coordinator, SigtermStopsInOrderToo) {
  StopSignal stop;
  InterruptingPhysics physics_sim(3, &stop, SIGTERM);
  SyntheticNetwork network_sim(Robots(0));
  auto physics =
      MakeInProcessConnector("phys0", Role::kPhysics, &physics_sim, Threading::kOwnThread);
  auto network =
      MakeInProcessConnector("net0", Role::kNetwork, &network_sim, Threading::kCallerThread);
  CoordinatorOptions options = Lockstep(1000);
  options.interrupt_fd = stop.fd();
  const RunResult result = RunCoordinator(*physics, *network, options);
  EXPECT_TRUE(result.interrupted);
  EXPECT_EQ(stop.signal_number(), SIGTERM);
  EXPECT_EQ(result.iterations_done, 4);  // In-process: iteration 3 runs to its end first.
}

}  // namespace
}  // namespace sitlnet::coordinator

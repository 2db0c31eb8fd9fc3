// The node link end to end, without root: node hosts are threads with in-memory ports, linked to
// the central over sockets. A lockstep run through RunCoordinator with the fleet as its physics
// makes the same medium calls, air frames, deliveries and writes as the run whose robots are all
// local; the accept step and a node's failure end in one line naming the node.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "coordinator/coordinator.h"
#include "fleet/node_link.h"
#include "fleet/node_ports.h"
#include "fleet/node_poses.h"
#include "fleet/test/bridge_fakes.h"
#include "network_side/network_side.h"

namespace sitlnet::fleet {
namespace {

using namespace test_support;
using coordinator::Channel;
using coordinator::Endpoint;
using coordinator::Listener;
using ::testing::HasSubstr;
using ::testing::MatchesRegex;

constexpr int kIterations = 40;
constexpr int kBurstIteration = 7, kBurstRobot = 3, kBurstFrames = 300;  // Over one turn.
constexpr int kFailIteration = 20, kFailRobot = 5;
constexpr int kJumpIteration = 10;  // Robot 0 leaves everyone's range.

// A node host's physics stand-in for some robots: each iteration every robot sends its traffic
// (RobotTraffic, seeded by the robot's index) to its tap before its command, then all commands
// are in; poses follow a rule of robot and time. Its faults, at an iteration:
struct Faults {
  int crash_at = -1;  // Throws NodeCrash, which ServeIterations does not catch: the socket closes.
  int hang_at = -1;   // Waits for `released` before anything.
  std::shared_future<void> released = {};
  int short_poses_at = -1;  // Ends with the poses of all robots but one.
  int fail_at = -1;         // Throws Error, as a node whose robot failed would.
};
struct NodeCrash {};
class FakePhysics final : public coordinator::Simulator {
 public:
  FakePhysics(const Scenario& scenario, std::vector<int> robots,
              std::function<MemoryTap&(int robot)> tap, Faults faults = {})
      : scenario_(scenario),
        robots_(std::move(robots)),
        tap_(std::move(tap)),
        faults_(std::move(faults)) {
    for (const int robot : robots_) rngs_.emplace(robot, std::mt19937_64(1000 + robot));
  }

  proto::coord::Poses InitialPoses() override { return PosesAt(0); }
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override {
    const int k = static_cast<int>(start.iteration());
    if (k == faults_.crash_at) throw NodeCrash{};
    if (k == faults_.hang_at) faults_.released.wait();
    for (const int robot : robots_) {
      const int burst = k == kBurstIteration && robot == kBurstRobot ? kBurstFrames : 0;
      MemoryTap& tap = tap_(robot);
      for (Frame& frame : RobotTraffic(scenario_, robot, &rngs_.at(robot), burst)) {
        tap.sent.push_back(std::move(frame));
      }
      if (k == kFailIteration && robot == kFailRobot) tap.read_errno = EIO;
    }
    context.CommandsCollected();
    *end->mutable_poses() = PosesAt(start.end_ns());
    if (k == faults_.fail_at) throw Error("robot 'r2' exited with status 1");
    if (k == faults_.short_poses_at) {
      end->mutable_poses()->mutable_position_m()->Truncate(3 * (robots_.size() - 1));
      end->mutable_poses()->mutable_orientation_wxyz()->Truncate(4 * (robots_.size() - 1));
    }
  }

 private:
  proto::coord::Poses PosesAt(TimeNs t_ns) const {
    proto::coord::Poses poses;
    for (const int robot : robots_) {
      const auto& at = scenario_.robots[robot].spec.position_m();
      const bool jumped = robot == 0 && t_ns > kJumpIteration * scenario_.iteration_ns;
      poses.add_position_m(at.x() + (jumped ? 200 : 0) + robot * (t_ns / 1e9));
      poses.add_position_m(at.y());
      poses.add_position_m(at.z());
      for (const double c : {1.0, 0.0, 0.0, 0.0}) poses.add_orientation_wxyz(c);
    }
    return poses;
  }

  const Scenario& scenario_;
  std::vector<int> robots_;
  std::function<MemoryTap&(int)> tap_;
  Faults faults_;
  std::map<int, std::mt19937_64> rngs_;
};

// A node host on a thread: its robots' taps in memory, NodePorts over them, the fake physics,
// and the node's end of the link (HandshakeWithCoordinator, ServeIterations).
class NodeHost {
 public:
  NodeHost(const Endpoint& endpoint, const Scenario& scenario, NodeSlice slice, Faults faults = {},
           std::string secret = {})
      : thread_([=, this, &scenario] {
          FakePhysics physics(
              scenario, slice.robots, [this](int robot) -> MemoryTap& { return taps_[robot]; },
              faults);
          NodePorts ports(
              slice, [this](int robot) { return std::make_unique<MemoryPort>(&taps_[robot]); });
          NodeSimulator node(&physics, &ports);
          try {
            Channel channel(coordinator::Connect(endpoint, MonotonicNowNs() + 5 * kNsPerS));
            const coordinator::ConnectorIdentity identity{
                slice.name, coordinator::Role::kNode, coordinator::ScenarioHash(scenario), secret};
            if (!HandshakeWithCoordinator(channel, identity, NodeHello(slice, node), 5 * kNsPerS)) {
              return;
            }
            stop_reason_ = ServeIterations(channel, node);
          } catch (const Error& e) {
            error_ = e.what();
          } catch (const NodeCrash&) {
            error_ = "crashed";
          }
        }) {}
  ~NodeHost() { Join(); }
  void Join() {
    if (thread_.joinable()) thread_.join();
  }
  // After Join.
  const std::string& error() const { return error_; }
  const std::string& stop_reason() const { return stop_reason_; }
  std::map<int, MemoryTap>& taps() { return taps_; }

 private:
  std::map<int, MemoryTap> taps_;
  std::string error_;
  std::string stop_reason_;
  std::thread thread_;  // Last: it uses the members above.
};

const NodeSlice kN0{"n0", {0, 3, 5, 6}};
const NodeSlice kN1{"n1", {1, 2, 4, 7}};  // Interleaved: the nodes' order is not the bridge's.

Listener UnixListener(const std::string& test) {
  return Listener(coordinator::ParseEndpoint("unix:/tmp/sitlnet-fleet-" + test + "-" +
                                             std::to_string(getpid())));
}

const std::string kSecret = "the fleet link test's shared secret";

coordinator::HandshakeExpectation Expect(const Scenario& scenario, std::string secret = {}) {
  coordinator::HandshakeExpectation expect;
  expect.scenario_hash = coordinator::ScenarioHash(scenario);
  expect.iteration_ns = scenario.iteration_ns;
  expect.lockstep_robots = true;
  expect.secret = std::move(secret);
  return expect;
}

coordinator::WaitLimits Within(TimeNs timeout_ns) {
  coordinator::WaitLimits limits;
  limits.timeout_ns = timeout_ns;
  limits.deadline_ns = MonotonicNowNs() + timeout_ns;
  return limits;
}

coordinator::CoordinatorOptions LockstepRobots(const Scenario& scenario, int iterations) {
  coordinator::CoordinatorOptions options = coordinator::OptionsFromScenario(scenario);
  options.iterations = iterations;
  options.pacing = coordinator::Pacing::kLockstep;
  options.lockstep_robots = true;
  return options;
}

tapbridge::BridgeOptions BridgeOver(std::function<std::unique_ptr<tapbridge::Port>(int)> open) {
  tapbridge::BridgeOptions options;
  options.seed = 9;
  options.open_port = std::move(open);
  return options;
}

// The central host of a two-node run: the nodes accepted, the bridge over their RemotePorts,
// the fleet as physics and the bridge as network, ready for RunCoordinator.
struct Central {
  Central(const Scenario& scenario, Listener& listener, BridgeLog* log, std::string secret = {})
      : ports(scenario, {kN0, kN1}),
        bridge(scenario, std::make_unique<RecordingMedium>(scenario, &log->calls),
               BridgeOver([this](int robot) { return ports.Open(robot); })),
        network_simulator(scenario, &bridge, coordinator::Pacing::kLockstep, 1.0),
        network(coordinator::MakeInProcessConnector("bridge", coordinator::Role::kNetwork,
                                                    &network_simulator,
                                                    coordinator::Threading::kCallerThread)) {
    Observe(&bridge, log);
    bridge.AttachAll();
    physics = std::make_unique<FleetPhysicsConnector>(
        scenario, coordinator::Pacing::kLockstep,
        AcceptNodes(listener, scenario, {kN0, kN1}, Expect(scenario, std::move(secret)),
                    Within(5 * kNsPerS)),
        &ports);
  }
  RemotePorts ports;
  tapbridge::BridgeCore bridge;
  network_side::BridgeSimulator network_simulator;
  std::unique_ptr<coordinator::Connector> network;
  std::unique_ptr<FleetPhysicsConnector> physics;
};

TEST(FleetLink, ALockstepRunOverTwoNodesDoesWhatItDoesOverLocalPorts) {
  const Scenario scenario = EightRobots();

  // One host: every robot's port local, the same physics for all of them in this process.
  BridgeLog local_log;
  std::vector<MemoryTap> local_taps(kRobots);
  tapbridge::BridgeCore local(
      scenario, std::make_unique<RecordingMedium>(scenario, &local_log.calls),
      BridgeOver([&](int robot) { return std::make_unique<MemoryPort>(&local_taps[robot]); }));
  Observe(&local, &local_log);
  local.AttachAll();
  FakePhysics local_physics(scenario, {0, 1, 2, 3, 4, 5, 6, 7},
                            [&](int robot) -> MemoryTap& { return local_taps[robot]; });
  network_side::BridgeSimulator local_network(scenario, &local, coordinator::Pacing::kLockstep,
                                              1.0);
  const auto local_physics_connector = coordinator::MakeInProcessConnector(
      "physics", coordinator::Role::kPhysics, &local_physics, coordinator::Threading::kOwnThread);
  const auto local_network_connector = coordinator::MakeInProcessConnector(
      "bridge", coordinator::Role::kNetwork, &local_network, coordinator::Threading::kCallerThread);
  // What the robots had received before the last iteration: a node gets that iteration's
  // deliveries with the next Start, which a run of kIterations never sends.
  std::vector<size_t> written_before_last(kRobots);
  coordinator::CoordinatorOptions local_options = LockstepRobots(scenario, kIterations);
  local_options.on_iteration = [&](const coordinator::IterationMetrics& m) {
    if (m.iteration != kIterations - 2) return;
    for (int robot = 0; robot < kRobots; ++robot) {
      written_before_last[robot] = local_taps[robot].written.size();
    }
  };
  EXPECT_EQ(
      coordinator::RunCoordinator(*local_physics_connector, *local_network_connector, local_options)
          .iterations_done,
      kIterations);

  // Two node hosts, their links authenticated (an HMAC tag per message).
  Listener listener = UnixListener("run");
  NodeHost n0(listener.endpoint(), scenario, kN0, {}, kSecret);
  NodeHost n1(listener.endpoint(), scenario, kN1, {}, kSecret);
  BridgeLog remote_log;
  Central central(scenario, listener, &remote_log, kSecret);
  EXPECT_EQ(coordinator::RunCoordinator(*central.physics, *central.network,
                                        LockstepRobots(scenario, kIterations))
                .iterations_done,
            kIterations);
  n0.Join();
  n1.Join();
  for (NodeHost* node : {&n0, &n1}) {
    EXPECT_EQ(node->error(), "");
    EXPECT_EQ(node->stop_reason(), "run complete");
  }

  ExpectSameLines(local_log.calls, remote_log.calls, "medium calls");
  ExpectSameLines(local_log.air, remote_log.air, "air frames");
  ExpectSameLines(local_log.deliveries, remote_log.deliveries, "deliveries");
  for (int robot = 0; robot < kRobots; ++robot) {
    const std::vector<Frame>& local_written = local_taps[robot].written;
    const std::vector<Frame> before_last(local_written.begin(),
                                         local_written.begin() + written_before_last[robot]);
    MemoryTap& node_tap = (std::ranges::count(kN0.robots, robot) ? n0 : n1).taps()[robot];
    EXPECT_TRUE(node_tap.written == before_last) << "robot " << robot << ": frames on the node";
  }
  // The last iteration's deliveries are still in the outboxes.
  NodeHost* nodes[2] = {&n0, &n1};
  for (int node = 0; node < 2; ++node) {
    const proto::node::NodeWrites left = central.ports.TakeWrites(node);
    for (const proto::node::NodeWrites::Write& write : left.writes()) {
      const std::string& frame = left.frames(write.frame_index());
      nodes[node]->taps()[write.robot()].written.emplace_back(frame.begin(), frame.end());
    }
  }
  for (int robot = 0; robot < kRobots; ++robot) {
    MemoryTap& node_tap = (std::ranges::count(kN0.robots, robot) ? n0 : n1).taps()[robot];
    EXPECT_TRUE(local_taps[robot].written == node_tap.written) << "robot " << robot;
    const tapbridge::PortCounters& l = local.port_counters(robot);
    const tapbridge::PortCounters& r = central.bridge.port_counters(robot);
    EXPECT_EQ(l.frames_read, r.frames_read) << robot;
    EXPECT_EQ(l.oversize_dropped, r.oversize_dropped) << robot;
    EXPECT_EQ(l.frames_written, r.frames_written) << robot;
    EXPECT_EQ(l.attached, r.attached) << robot;
  }
  // The run exercised what it claims to: traffic got through, the burst spilled into a second
  // turn, the failed read detached its robot, and robot 0's jump changed who hears whom.
  EXPECT_GT(remote_log.deliveries.size(), 100u);
  EXPECT_GT(central.bridge.port_counters(kBurstRobot).frames_read,
            static_cast<uint64_t>(kBurstFrames));
  EXPECT_FALSE(central.bridge.port_counters(kFailRobot).attached);
  EXPECT_THAT(remote_log.calls, ::testing::Contains(HasSubstr("position 0 200")));
}

// How a two-node run whose nodes have `faults` ended: its error, and each node's.
struct FaultyRun {
  std::string error;
  std::string node_errors[2];
  std::string node_stop_reasons[2];
};
FaultyRun RunWithFaults(
    const std::string& test, const Faults (&faults)[2], TimeNs answer_timeout_ns = 5 * kNsPerS,
    const std::function<void()>& after_run = [] {}) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener(test);
  NodeHost n0(listener.endpoint(), scenario, kN0, faults[0]);
  NodeHost n1(listener.endpoint(), scenario, kN1, faults[1]);
  BridgeLog log;
  Central central(scenario, listener, &log);
  coordinator::CoordinatorOptions options = LockstepRobots(scenario, 10);
  options.answer_timeout_ns = answer_timeout_ns;
  FaultyRun run;
  try {
    coordinator::RunCoordinator(*central.physics, *central.network, options);
  } catch (const Error& e) {
    run.error = e.what();
  }
  after_run();
  n0.Join();
  n1.Join();
  for (int node = 0; node < 2; ++node) {
    run.node_errors[node] = (node == 0 ? n0 : n1).error();
    run.node_stop_reasons[node] = (node == 0 ? n0 : n1).stop_reason();
  }
  return run;
}

TEST(FleetLink, ANodeThatClosesMidRunIsNamedWithItsRobotsAndTheIteration) {
  const FaultyRun run = RunWithFaults("close", {{}, {.crash_at = 5}});
  EXPECT_EQ(run.error,
            "node 'n1' (robots r1, r2, r4, r7) failed during iteration 5: peer closed the "
            "connection (node crashed or exited)");
  EXPECT_EQ(run.node_errors[1], "crashed");
  EXPECT_EQ(run.node_errors[0], "");
  EXPECT_EQ(run.node_stop_reasons[0], "coordinator failed");  // The survivor is stopped.
}

TEST(FleetLink, ASilentNodeIsNamedAtTheAnswerTimeout) {
  std::promise<void> release;
  const FaultyRun run =
      RunWithFaults("silent", {{.hang_at = 3, .released = release.get_future().share()}, {}},
                    200 * kNsPerMs, [&] { release.set_value(); });
  EXPECT_EQ(run.error,
            "node 'n0' (robots r0, r3, r5, r6) did not answer START of iteration 3 with "
            "CommandsCollected within 200 ms");
  EXPECT_EQ(run.node_stop_reasons[1], "coordinator failed");
}

TEST(FleetLink, ANodeEndingWithTooFewPosesIsNamed) {
  const FaultyRun run = RunWithFaults("poses", {{}, {.short_poses_at = 2}});
  EXPECT_EQ(run.error,
            "node 'n1' (robots r1, r2, r4, r7): End of iteration 2: sent 9 position, 12 "
            "orientation and 0 velocity numbers, not 3, 4 and 3 (or 0) for each of its 4 robots");
  EXPECT_EQ(run.node_stop_reasons[1], "coordinator failed");
}

TEST(FindBrokenPoses, ANumberThatIsNotFiniteIsNamedWithItsRobot) {
  proto::coord::Poses poses;
  for (int i = 0; i < 6; ++i) poses.add_position_m(1.5);
  for (int i = 0; i < 8; ++i) poses.add_orientation_wxyz(0.5);
  EXPECT_EQ(FindBrokenPoses(poses, 2), std::nullopt);
  poses.set_orientation_wxyz(5, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(FindBrokenPoses(poses, 2),
            "sent its robot 2's orientation (of 2 robots) with a number that is not finite");
  poses.set_orientation_wxyz(5, 0.5);
  for (int i = 0; i < 6; ++i) poses.add_velocity_m_s(0);
  poses.set_velocity_m_s(2, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(FindBrokenPoses(poses, 2),
            "sent its robot 1's velocity (of 2 robots) with a number that is not finite");
}

TEST(FleetLink, ANodesOwnErrorReachesTheCentralNamingTheNode) {
  const FaultyRun run = RunWithFaults("error", {{}, {.fail_at = 4}});
  EXPECT_EQ(run.error,
            "node 'n1' (robots r1, r2, r4, r7) reported an error in iteration 4: robot 'r2' exited "
            "with status 1");
  EXPECT_EQ(run.node_errors[1], "robot 'r2' exited with status 1");
  EXPECT_EQ(run.node_stop_reasons[0], "coordinator failed");
}

TEST(FleetLink, MoreThanOneNetworkStepPerIterationIsRefused) {
  const Scenario scenario = LoadScenarioText(
      "name: \"fleet\"\ntiming { pacing: PACING_LOCKSTEP network_step_us: 5000 }\n"
      "robot { name: \"r0\" position_m { x: 0 y: 0 z: 1 } }\n",
      "fleet_link_test");
  RemotePorts ports(scenario, {{"n0", {0}}});
  try {
    FleetPhysicsConnector(scenario, coordinator::Pacing::kLockstep, {}, &ports);
    ADD_FAILURE() << "accepted two network steps per iteration";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "scenario fleet: robots on node hosts in lockstep pacing need one network step per "
              "iteration for now (network_step_us equal to iteration_us; issue 35)");
  }
}

//-------------------------------- AcceptNodes --------------------------------

// AcceptNodes' error, or "" when it accepted every node (then it stops them).
std::string AcceptError(Listener& listener, const Scenario& scenario, TimeNs timeout_ns,
                        std::string secret = {}) {
  try {
    for (const auto& link : AcceptNodes(listener, scenario, {kN0, kN1},
                                        Expect(scenario, std::move(secret)), Within(timeout_ns))) {
      link->connector().Stop("test over");
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(AcceptNodes, AnUnknownNodeIsRefusedNamingTheNodes) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener("unknown");
  NodeHost n9(listener.endpoint(), scenario, {"n9", kN0.robots});
  const std::string error = AcceptError(listener, scenario, 5 * kNsPerS);
  EXPECT_EQ(error, "node 'n9' is not one of this run's nodes (n0, n1)");
  n9.Join();
  EXPECT_EQ(n9.error(), "the coordinator refused: " + error);
}

TEST(AcceptNodes, ANodeOfAnotherScenarioIsRefusedWithBothHashes) {
  const Scenario scenario = EightRobots();
  const Scenario another_seed = EightRobots(6);
  Listener listener = UnixListener("hash");
  NodeHost n0(listener.endpoint(), another_seed, kN0);
  const std::string error = AcceptError(listener, scenario, 5 * kNsPerS);
  EXPECT_THAT(error, MatchesRegex("node 'n0' loaded a different scenario: hash 0x[0-9a-f]{16}, "
                                  "the coordinator's is 0x[0-9a-f]{16}"));
  n0.Join();
  EXPECT_EQ(n0.error(), "the coordinator refused: " + error);
}

TEST(AcceptNodes, ANodeClaimingOtherRobotsIsRefused) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener("robots");
  NodeHost n1(listener.endpoint(), scenario, {"n1", {1, 2}});
  const std::string error = AcceptError(listener, scenario, 5 * kNsPerS);
  EXPECT_EQ(error,
            "node 'n1' claims robots r1, r2, but the scenario gives it r1, r2, r4, r7 (another "
            "scenario or --node?)");
  n1.Join();
  EXPECT_EQ(n1.error(), "the coordinator refused: " + error);
}

TEST(AcceptNodes, TwoNodesOfOneNameAreRefusedWithTheirAddresses) {
  const Scenario scenario = EightRobots();
  Listener listener(coordinator::ParseEndpoint("127.0.0.1:0"));
  NodeHost first(listener.endpoint(), scenario, kN0);
  NodeHost second(listener.endpoint(), scenario, kN0);
  const std::string error = AcceptError(listener, scenario, 5 * kNsPerS);
  EXPECT_THAT(error,
              MatchesRegex("two nodes claim robot 'r0': node 'n0' from 127\\.0\\.0\\.1:[0-9]+"
                           " and node 'n0' from 127\\.0\\.0\\.1:[0-9]+"));
  first.Join();
  second.Join();
  EXPECT_EQ(first.stop_reason(), error);  // Both told why, and ended.
  EXPECT_EQ(second.stop_reason(), error);
}

TEST(AcceptNodes, AMissingNodeIsNamedWithItsRobotsAtTheDeadline) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener("missing");
  NodeHost n0(listener.endpoint(), scenario, kN0);
  const std::string error = AcceptError(listener, scenario, 300 * kNsPerMs);
  EXPECT_EQ(error, "node 'n1' (robots r1, r2, r4, r7) did not connect to " +
                       listener.endpoint().ToString() + " within 300 ms");
  n0.Join();
  EXPECT_EQ(n0.stop_reason(), error);  // The node that came is stopped, told why.
}

TEST(AcceptNodes, ANodeWithAnotherSecretIsIgnoredAndNamedAtTheDeadline) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener("secret");
  NodeHost n0(listener.endpoint(), scenario, kN0, {}, kSecret);
  NodeHost n1(listener.endpoint(), scenario, kN1, {}, "another secret of enough bytes");
  const std::string error = AcceptError(listener, scenario, 300 * kNsPerMs, kSecret);
  EXPECT_EQ(error, "node 'n1' (robots r1, r2, r4, r7) did not connect to " +
                       listener.endpoint().ToString() + " within 300 ms");
  n0.Join();
  n1.Join();
  EXPECT_EQ(n0.stop_reason(), error);
  EXPECT_EQ(n1.error(),
            "the coordinator failed to prove the shared secret (a different --secret-file, or not "
            "sitlnet's coordinator)");
}

TEST(AcceptNodes, APhysicsConnectorIsRefusedByAFleetAndANodeByAPlainCoordinator) {
  const Scenario scenario = EightRobots();
  Listener listener = UnixListener("roles");
  std::string refusal;
  std::thread physics([&] {
    try {
      Channel channel(coordinator::Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS));
      coordinator::HandshakeWithCoordinator(
          channel, {"phys", coordinator::Role::kPhysics, coordinator::ScenarioHash(scenario), {}},
          {}, kNsPerS);
    } catch (const Error& e) {
      refusal = e.what();
    }
  });
  EXPECT_EQ(AcceptError(listener, scenario, 5 * kNsPerS),
            "physics connector 'phys' connected, but this coordinator waits for a node");
  physics.join();
  EXPECT_THAT(refusal, HasSubstr("waits for a node"));

  NodeHost n0(listener.endpoint(), scenario, kN0);
  try {
    coordinator::AcceptConnectors(listener, Expect(scenario), Within(5 * kNsPerS));
    ADD_FAILURE() << "a plain coordinator took a node";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "node 'n0' connected, but this coordinator runs no fleet (its scenario has no "
              "nodes)");
  }
}

}  // namespace
}  // namespace sitlnet::fleet

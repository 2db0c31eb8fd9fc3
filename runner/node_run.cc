#include "runner/node_run.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <vector>

#include "coordinator/coordinator.h"
#include "fleet/node_ports.h"
#include "physics_side/physics_side.h"
#include "runner/gcs_relay_stage.h"
#include "runner/iteration_observer.h"
#include "runner/physics_options.h"
#include "runner/robot_host.h"
#include "runner/robot_start.h"
#include "runner/robot_stop.h"
#include "runner/robot_supervisor.h"
#include "runner/run_folder.h"
#include "tapbridge/tap_port.h"

namespace sitlnet::runner {
namespace {

// The slice of node `name`; throws Error naming the scenario's nodes if there is none.
fleet::NodeSlice SliceOf(const Scenario& scenario, const std::string& name) {
  const int node = scenario.NodeIndex(name);
  if (node < 0) {
    std::string names;
    for (const NodePlan& plan : scenario.nodes) names += (names.empty() ? "" : ", ") + plan.name;
    throw Error("node '" + name + "' is not in scenario " + scenario.name +
                " (nodes: " + (names.empty() ? "none" : names) + ")");
  }
  return {scenario.nodes[node].name, scenario.nodes[node].robots};
}

void RefuseUnsupported(const Scenario& scenario) {
  if (scenario.spec.timing().ros2_clock_hz() > 0) {
    throw Error("scenario " + scenario.name +
                ": timing.ros2_clock_hz is not served on node hosts yet (issue 35)");
  }
}

// A node's robots brought up, in this order, and torn down in the reverse order however the
// node ends: their namespaces, the physics of them only, their images (spoken to physics).
// Realtime: the autopilots are served on `realtime`, this node's clock of the run (begun by the
// central's first Start, fleet::NodeSimulator).
class NodeSetup {
 public:
  NodeSetup(const Scenario& scenario, const RunOptions& options, const std::string& out_dir,
            const fleet::NodeSlice& slice, const clock::Timebase* realtime)
      : namespaces_(scenario, slice.robots),
        physics_server_(scenario,
                        RunPhysicsOptions(scenario, scenario.lockstep(), realtime, slice.robots)),
        robots_(StartImages(scenario, options, out_dir, slice.robots)) {
    // As on one host (RunSetup::StartRobots).
    if (scenario.lockstep() || scenario.spec.timing().wait_for_robots()) {
      WaitForRobotsToSpeak(scenario, robots_, &physics_server_,
                           scenario.lockstep() ? "lockstep" : "wait_for_robots");
    }
  }
  ~NodeSetup() {
    RunReport ignored;  // The robots' usage is the central's business no more.
    std::vector<std::unique_ptr<images::RobotProcess>> no_clock_publishers;
    StopRobots(&robots_, &no_clock_publishers, &ignored);
  }
  NodeSetup(const NodeSetup&) = delete;
  NodeSetup& operator=(const NodeSetup&) = delete;

  physics::PhysicsServer& physics_server() { return physics_server_; }
  std::vector<RobotSlot>& robots() { return robots_; }

 private:
  ScenarioNamespaces namespaces_;
  physics::PhysicsServer physics_server_;
  std::vector<RobotSlot> robots_;
};

// The relay of the scenario's ground station when this node runs it: the relay enters the
// station's namespace, which exists on this host only (docs/autopilots.md, "Ground stations").
// Null when the station is another node's, there is none, or --gcs none.
std::unique_ptr<gcs::GcsRelay> StartNodeGcsRelay(const Scenario& scenario,
                                                 const fleet::NodeSlice& slice,
                                                 const RunOptions& options,
                                                 const std::string& out_dir) {
  const RobotPlan* station = RelayedGroundStation(scenario);
  if (station == nullptr ||
      std::find(slice.robots.begin(), slice.robots.end(), station->index) == slice.robots.end()) {
    return nullptr;
  }
  return StartGcsRelay(scenario, GcsEndpointsOf(options.gcs), out_dir, options.program);
}

coordinator::Channel ConnectToCentral(const coordinator::Endpoint& endpoint, TimeNs timeout_ns) {
  try {
    return coordinator::Channel(coordinator::Connect(endpoint, MonotonicNowNs() + timeout_ns));
  } catch (const coordinator::TransportError& e) {
    throw Error("cannot reach the central host at " + endpoint.ToString() + ": " + e.what());
  }
}

}  // namespace

std::string ServeNodeHost(const NodeOptions& options) {
  const Scenario scenario =
      ApplyRunOverrides(LoadScenarioFile(options.run.scenario_path), options.run);
  const fleet::NodeSlice slice = SliceOf(scenario, options.node);
  RefuseUnsupported(scenario);
  const coordinator::Endpoint endpoint = coordinator::ParseEndpoint(options.connect);
  GcsEndpointsOf(options.run.gcs);  // A bad --gcs is refused before anything is created.
  const std::string secret = options.run.secret_file.empty()
                                 ? std::string()
                                 : coordinator::LoadSecretFile(options.run.secret_file);
  PrepareRobotHost(scenario, slice.robots.size());
  StopSignal stop;  // Ctrl-C from here on stops in order.
  const std::string out_dir = options.run.out_dir.empty()
                                  ? "runs/" + scenario.name + "-" + slice.name
                                  : options.run.out_dir;
  MakeRunFolder(out_dir);
  const std::string described = fleet::DescribeNode(scenario, slice);
  std::fprintf(stderr, "sitlnet node: %s: bringing up %s -> %s\n", scenario.name.c_str(),
               described.c_str(), out_dir.c_str());
  // Realtime: the node's physics and TAP reads at the priority one host gives them.
  if (!scenario.lockstep())
    RequestRealtimeRunPriority(options.run.realtime_priority, "sitlnet node");
  clock::Timebase realtime(scenario.spec.timing().realtime_factor());  // Lockstep: unused.
  NodeSetup setup(scenario, options.run, out_dir, slice, &realtime);
  const std::unique_ptr<gcs::GcsRelay> gcs_relay =
      StartNodeGcsRelay(scenario, slice, options.run, out_dir);
  // gcs.tlog is stamped with each iteration's start in both pacings: this node's realtime clock
  // may begin again when it runs late (NodeSimulator), and the relay keeps the one it was given.
  std::optional<GcsRelayClock> gcs_clock;
  if (gcs_relay) gcs_clock.emplace(gcs_relay.get(), &realtime, /*lockstep=*/true);

  physics_side::PhysicsServerSimulator physics(scenario, &setup.physics_server(),
                                               RobotLockstep(scenario, scenario.lockstep()));
  fleet::NodePorts ports(slice, [&scenario](int robot) {
    return std::make_unique<tapbridge::TapPort>(scenario.robots[robot].netns, "wlan0");
  });
  fleet::NodeSimulator node(&physics, &ports, scenario.lockstep() ? nullptr : &realtime);
  RobotSupervisor supervisor(
      &setup.robots(), scenario.spec.on_robot_failure() == proto::Scenario::ROBOT_FAILURE_STOP,
      nullptr, options.run.program);
  std::vector<IterationObserver*> observers = {&supervisor};
  if (gcs_clock) observers.push_back(&*gcs_clock);
  ObservedSimulator supervised(&node, observers);

  std::fprintf(stderr, "sitlnet node: %s: connecting to the central host at %s\n",
               described.c_str(), endpoint.ToString().c_str());
  coordinator::Channel channel = ConnectToCentral(endpoint, options.connect_timeout_ns);
  const coordinator::ConnectorIdentity identity{slice.name, coordinator::Role::kNode,
                                                fleet::NodeScenarioHash(scenario), secret};
  if (!coordinator::HandshakeWithCoordinator(channel, identity, fleet::NodeHello(slice, supervised),
                                             options.connect_timeout_ns, stop.fd())) {
    return "interrupted";
  }
  // Readiness is timed from the run's start: the images waited for the central meanwhile.
  for (RobotSlot& robot : setup.robots()) robot.started_wall_ns = MonotonicNowNs();
  const uint64_t sent_before = channel.bytes_sent(), received_before = channel.bytes_received();
  const std::string reason = coordinator::ServeIterations(channel, supervised, stop.fd());
  // The node's count of its link, the other end of the central's (summary.json "fleet_links").
  std::fprintf(stderr,
               "sitlnet node: %s: %llu B sent to the central host and %llu B received after the "
               "handshake\n",
               described.c_str(),
               static_cast<unsigned long long>(channel.bytes_sent() - sent_before),
               static_cast<unsigned long long>(channel.bytes_received() - received_before));
  StopGcsRelay(gcs_relay.get(), options.run.program);  // Its counts on stderr only.
  return reason;
}

}  // namespace sitlnet::runner

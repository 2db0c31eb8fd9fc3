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
#include "runner/run_stages.h"
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

// What serves the central's iterations on a node: the physics of its robots, their TAPs, the
// node's side of the link, its robots supervised (and the relay's clock, if any, told).
struct NodeService {
  NodeService(const Scenario& scenario, const fleet::NodeSlice& slice, NodeSetup* setup,
              clock::Timebase* realtime, GcsRelayClock* gcs_clock, const std::string& program)
      : physics(scenario, &setup->physics_server(), RobotLockstep(scenario, scenario.lockstep())),
        ports(slice,
              [&scenario](int robot) {
                return std::make_unique<tapbridge::TapPort>(scenario.robots[robot].netns, "wlan0");
              }),
        node(&physics, &ports, scenario.lockstep() ? nullptr : realtime),
        supervisor(&setup->robots(),
                   scenario.spec.on_robot_failure() == proto::Scenario::ROBOT_FAILURE_STOP, nullptr,
                   program),
        supervised(&node, gcs_clock ? std::vector<IterationObserver*>{&supervisor, gcs_clock}
                                    : std::vector<IterationObserver*>{&supervisor}) {}

  physics_side::PhysicsServerSimulator physics;
  fleet::NodePorts ports;
  fleet::NodeSimulator node;
  RobotSupervisor supervisor;
  ObservedSimulator supervised;
};

// A node host: the run's stages (runner/run_stages.h). The outputs are the central's.
class NodeHostRun final : public RunStages {
 public:
  // Loads the scenario and finds this node's slice (throws Error naming them).
  explicit NodeHostRun(const NodeOptions& options)
      : options_(options),
        scenario_(ApplyRunOverrides(LoadScenarioFile(options.run.scenario_path), options.run)),
        slice_(SliceOf(scenario_, options.node)),
        realtime_(scenario_.spec.timing().realtime_factor()) {}
  // The reason of the central's Stop, or "interrupted".
  const std::string& reason() const { return reason_; }

 protected:
  void Refuse() override {
    RefuseUnsupported(scenario_);
    endpoint_ = coordinator::ParseEndpoint(options_.connect);
    GcsEndpointsOf(options_.run.gcs);  // A bad --gcs is refused before anything is created.
    if (!options_.run.secret_file.empty()) {
      secret_ = coordinator::LoadSecretFile(options_.run.secret_file);
    }
  }
  void PrepareHost() override { PrepareRobotHost(scenario_, slice_.robots.size()); }
  bool Open(int /*stop_fd*/) override {
    out_dir_ = options_.run.out_dir.empty() ? "runs/" + scenario_.name + "-" + slice_.name
                                            : options_.run.out_dir;
    MakeRunFolder(out_dir_);
    described_ = fleet::DescribeNode(scenario_, slice_);
    std::fprintf(stderr, "sitlnet node: %s: bringing up %s -> %s\n", scenario_.name.c_str(),
                 described_.c_str(), out_dir_.c_str());
    return true;
  }
  void SetUp() override {
    // Realtime: the node's physics and TAP reads at the priority one host gives them.
    if (!scenario_.lockstep()) {
      RequestRealtimeRunPriority(options_.run.realtime_priority, "sitlnet node");
    }
    setup_ = std::make_unique<NodeSetup>(scenario_, options_.run, out_dir_, slice_, &realtime_);
    gcs_relay_ = StartNodeGcsRelay(scenario_, slice_, options_.run, out_dir_);
    // gcs.tlog is stamped with each iteration's start in both pacings: this node's realtime
    // clock may begin again when it runs late (NodeSimulator), and the relay keeps the one it
    // was given.
    if (gcs_relay_) gcs_clock_.emplace(gcs_relay_.get(), &realtime_, /*lockstep=*/true);
  }
  // Connects to the central and serves its iterations until its Stop.
  bool Loop(int stop_fd) override {
    service_ =
        std::make_unique<NodeService>(scenario_, slice_, setup_.get(), &realtime_,
                                      gcs_clock_ ? &*gcs_clock_ : nullptr, options_.run.program);
    std::fprintf(stderr, "sitlnet node: %s: connecting to the central host at %s\n",
                 described_.c_str(), endpoint_.ToString().c_str());
    channel_.emplace(ConnectToCentral(endpoint_, options_.connect_timeout_ns));
    const coordinator::ConnectorIdentity identity{slice_.name, coordinator::Role::kNode,
                                                  fleet::NodeScenarioHash(scenario_), secret_};
    if (!coordinator::HandshakeWithCoordinator(*channel_, identity,
                                               fleet::NodeHello(slice_, service_->supervised),
                                               options_.connect_timeout_ns, stop_fd)) {
      reason_ = "interrupted";
      return false;
    }
    // Readiness is timed from the run's start: the images waited for the central meanwhile.
    for (RobotSlot& robot : setup_->robots()) robot.started_wall_ns = MonotonicNowNs();
    const uint64_t sent_before = channel_->bytes_sent();
    const uint64_t received_before = channel_->bytes_received();
    reason_ = coordinator::ServeIterations(*channel_, service_->supervised, stop_fd);
    // The node's count of its link, the other end of the central's (summary.json "fleet_links").
    std::fprintf(stderr,
                 "sitlnet node: %s: %llu B sent to the central host and %llu B received after the "
                 "handshake\n",
                 described_.c_str(),
                 static_cast<unsigned long long>(channel_->bytes_sent() - sent_before),
                 static_cast<unsigned long long>(channel_->bytes_received() - received_before));
    return true;
  }
  // The robots stop when the setup goes (~NodeSetup).
  void Stop() override { StopGcsRelay(gcs_relay_.get(), options_.run.program); }

 private:
  const NodeOptions& options_;
  const Scenario scenario_;
  const fleet::NodeSlice slice_;
  coordinator::Endpoint endpoint_;
  std::string secret_;
  std::string out_dir_;
  std::string described_;
  clock::Timebase realtime_;  // This node's clock of the run in realtime; lockstep: unused.
  // Destroyed in the reverse order: the link, the service, the relay, then the robots.
  std::unique_ptr<NodeSetup> setup_;
  std::unique_ptr<gcs::GcsRelay> gcs_relay_;
  std::optional<GcsRelayClock> gcs_clock_;
  std::unique_ptr<NodeService> service_;
  std::optional<coordinator::Channel> channel_;
  std::string reason_;
};

}  // namespace

std::string ServeNodeHost(const NodeOptions& options) {
  NodeHostRun run(options);
  run.Run();
  return run.reason();
}

}  // namespace sitlnet::runner

#include "runner/fleet_run.h"

#include <cstdio>
#include <memory>
#include <vector>

#include "coordinator/coordinator.h"
#include "fleet/node_link.h"
#include "runner/central_stages.h"
#include "runner/cpu_time.h"
#include "runner/gcs_relay_stage.h"
#include "runner/physics_options.h"
#include "runner/recording_connector.h"
#include "runner/remote_network.h"
#include "runner/run_folder.h"
#include "runner/run_medium.h"
#include "runner/run_parts.h"

namespace sitlnet::runner {
namespace {

// What a central host refuses before it listens.
void RefuseFleetOptions(const Scenario& scenario, const RunOptions& options) {
  if (options.remote_network) {
    throw Error("scenario " + scenario.name +
                " has nodes: its robots run on node hosts, and --remote network moves the medium "
                "away from them; give one or the other (or --one-host)");
  }
  // The relay runs where the station's namespace is: on its node host (runner/node_run.cc).
  if (const RobotPlan* station = RelayedGroundStation(scenario);
      station != nullptr && !options.gcs.empty() &&
      options.gcs != std::vector<std::string>{"none"}) {
    throw Error("--gcs: ground station \"" + station->name + "\" runs on node '" +
                scenario.nodes[station->node].name +
                "', and its MAVLink is relayed there: give --gcs to that `sitlnet node`");
  }
  if (options.listen.empty()) {
    throw Error("scenario " + scenario.name +
                " has nodes: give --listen HOST:PORT for their `sitlnet node` (or --one-host to "
                "run every robot here)");
  }
}

// Every node host, accepted on options.listen; empty if interrupted (Ctrl-C). Throws Error
// naming a node that did not come, or was refused.
std::vector<std::unique_ptr<fleet::NodeLink>> AcceptNodeHosts(const Scenario& scenario,
                                                              const RunOptions& options,
                                                              int interrupt_fd) {
  PeerListener peers = ListenForPeers(scenario, options,
                                      {std::to_string(scenario.nodes.size()) + " nodes",
                                       "sitlnet node FILE --node NAME --connect HOST:PORT",
                                       fleet::NodeScenarioHash(scenario), options.node_wait_ns},
                                      interrupt_fd);
  peers.expect.lockstep_robots = scenario.lockstep();
  auto nodes =
      fleet::AcceptNodes(*peers.listener, scenario, scenario.nodes, peers.expect, peers.limits);
  for (const auto& node : nodes) {
    std::fprintf(stderr, "sitlnet run: %s connected\n", node->Describe().c_str());
  }
  return nodes;  // The listener closes: nothing else can connect.
}

// The physics of the node hosts, as one connector, recording trajectories.csv centrally.
class FleetPhysics final : public RunPhysics {
 public:
  FleetPhysics(const Scenario& scenario, std::vector<std::unique_ptr<fleet::NodeLink>> nodes,
               fleet::RemotePorts* ports, const RunOptions& options, const std::string& run_dir)
      : fleet_(scenario, scenario.pacing(), std::move(nodes), ports),
        recording_(&fleet_, physics::GeodeticFrame(scenario.spec.geodetic_origin()),
                   run_dir + "/trajectories.csv", options.trajectory_period_ns) {}
  coordinator::Connector& connector() override { return recording_; }
  void Flush() override { recording_.Flush(); }
  std::optional<run_formats::ClosestApproach> closest_approach() const override {
    return recording_.closest_approach();
  }
  std::vector<fleet::FleetLinkStats> link_stats() const { return fleet_.link_stats(); }

 private:
  fleet::FleetPhysicsConnector fleet_;
  RecordingConnector recording_;
};

// The central host's setup: the bridge over the node hosts' robots (RemotePorts), the medium and
// its records, the fleet as the physics. No namespace, no image: they are the nodes'.
class FleetSetup final : public RunParts {
 public:
  FleetSetup(const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
             std::vector<std::unique_ptr<fleet::NodeLink>> nodes)
      : scenario_(scenario),
        run_timebase_(scenario.spec.timing().realtime_factor()),
        ports_(scenario, scenario.nodes, scenario.lockstep() ? nullptr : &run_timebase_),
        robots_(scenario.robots.size()) {
    for (const RobotPlan& plan : scenario.robots) robots_[plan.index].name = plan.name;
    // The nodes' link first: the medium's records need the run folder only.
    physics_ =
        std::make_unique<FleetPhysics>(scenario, std::move(nodes), &ports_, options, run_dir);
    medium_ = std::make_unique<RunMedium>(scenario, options, run_dir, nullptr,
                                          [this](int robot) { return ports_.Open(robot); });
  }

  FleetPhysics& physics() { return *physics_; }
  const Scenario& scenario() const override { return scenario_; }
  bool lockstep() const override { return scenario_.lockstep(); }
  const fleet::RemotePorts& ports() const { return ports_; }
  tapbridge::BridgeCore& bridge() override { return medium_->bridge(); }
  MediumRecords& medium_records() override { return medium_->records(); }
  std::vector<RobotSlot>& robots() override { return robots_; }
  clock::Timebase& run_timebase() override { return run_timebase_; }
  network_side::RemoteMedium* remote_medium() override { return nullptr; }
  const physics::PhysicsServer* local_physics() const override { return nullptr; }

 private:
  const Scenario& scenario_;
  clock::Timebase run_timebase_;   // Before ports_, which read it in realtime.
  fleet::RemotePorts ports_;       // Outlives the bridge, whose ports are its.
  std::vector<RobotSlot> robots_;  // Names only: the images run on the nodes.
  std::unique_ptr<RunMedium> medium_;
  std::unique_ptr<FleetPhysics> physics_;  // Destroyed first: the nodes hear Stop before.
};

// Realtime: how late each node's frames entered the medium and its deliveries were written
// (ReportRun logs them, summary.json's "fleet_realtime").
std::vector<RunReport::NodeLateness> RealtimeNodes(const Scenario& scenario,
                                                   const fleet::RemotePorts& ports) {
  std::vector<RunReport::NodeLateness> nodes;
  for (size_t node = 0; node < scenario.nodes.size(); ++node) {
    nodes.push_back({scenario.nodes[node].name, fleet::DescribeNode(scenario, scenario.nodes[node]),
                     ports.LateEntries(static_cast<int>(node)),
                     ports.LateWrites(static_cast<int>(node))});
  }
  return nodes;
}

// A fleet's central host: the run's stages (runner/run_stages.h). Nothing namespaced, no image.
class FleetCentralRun final : public CentralStages {
 public:
  using CentralStages::CentralStages;

 protected:
  void Refuse() override { RefuseFleetOptions(scenario_, options_); }
  // The node hosts, accepted before anything exists; then the run folder.
  bool Open(int stop_fd) override {
    if (const RobotPlan* station = RelayedGroundStation(scenario_)) {
      std::fprintf(stderr,
                   "sitlnet run: ground station \"%s\" is on node '%s': its `sitlnet node` relays "
                   "its MAVLink to a GCS (docs/autopilots.md, \"Ground stations\")\n",
                   station->name.c_str(), scenario_.nodes[station->node].name.c_str());
    }
    try {
      nodes_ = AcceptNodeHosts(scenario_, options_, stop_fd);
    } catch (const Error& error) {
      std::fprintf(stderr, "sitlnet run: %s\n", error.what());
      report_.exit_code = 1;
      return false;
    }
    if (nodes_.empty()) {
      report_.interrupted = true;
      report_.exit_code = 130;
      return false;
    }
    MakeRunFolder(report_.run_dir);
    WriteEffectiveScenario(scenario_, report_.run_dir);
    return true;
  }
  void SetUp() override {
    // Realtime: the bridge at the priority one host gives it.
    if (!scenario_.lockstep()) {
      RequestRealtimeRunPriority(options_.realtime_priority, "sitlnet run");
    }
    setup_ = std::make_unique<FleetSetup>(scenario_, options_, report_.run_dir, std::move(nodes_));
  }
  RunParts& parts() override { return *setup_; }
  RunPhysics& physics() override { return setup_->physics(); }
  void Stop() override {
    setup_->medium_records().Flush();
    report_.fleet_links = setup_->physics().link_stats();
    if (!scenario_.lockstep()) report_.fleet_realtime = RealtimeNodes(scenario_, setup_->ports());
  }

 private:
  std::vector<std::unique_ptr<fleet::NodeLink>> nodes_;  // Until the setup takes them.
  std::unique_ptr<FleetSetup> setup_;
};

}  // namespace

RunReport RunOnNodeHosts(const Scenario& scenario, const RunOptions& options, RunReport report,
                         TimeNs begin_ns) {
  FleetCentralRun run(scenario, options, std::move(report), begin_ns);
  run.Run();
  return run.TakeReport();
}

}  // namespace sitlnet::runner

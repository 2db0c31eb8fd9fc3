// `sitlnet run`: loads the scenario, then runs its stages (runner/run_stages.h) on this host, or
// as the central host of its node hosts (runner/fleet_run.cc).
#include <sys/resource.h>

#include <ctime>
#include <memory>

#include "coordinator/coordinator.h"
#include "runner/central_stages.h"
#include "runner/cpu_time.h"
#include "runner/fleet_run.h"
#include "runner/gcs_relay_stage.h"
#include "runner/local_physics.h"
#include "runner/remote_network.h"
#include "runner/robot_host.h"
#include "runner/robot_stop.h"
#include "runner/run_folder.h"
#include "runner/run_record.h"
#include "runner/run_setup.h"
#include "runner/runner.h"

namespace sitlnet::runner {
namespace {

Scenario LoadWithOverrides(const RunOptions& options) {
  return ApplyRunOverrides(options.scenario_text
                               ? LoadScenarioText(*options.scenario_text, options.scenario_path)
                               : LoadScenarioFile(options.scenario_path),
                           options);
}

std::string DefaultRunDir(const std::string& scenario_name) {
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  return "runs/" + scenario_name + "-" + stamp;
}

// `--listen` is for the medium (--remote network) or for node hosts (a scenario with nodes).
bool RunsOnNodeHosts(const Scenario& scenario, const RunOptions& options) {
  if (!scenario.nodes.empty() && !options.one_host) return true;
  if (!options.listen.empty() && !options.remote_network) {
    throw Error("--listen is for --remote network, or for the node hosts of a scenario with nodes" +
                std::string(options.one_host ? " (not with --one-host)" : ""));
  }
  return false;
}

// `--remote network` is refused in realtime pacing, before anything is created.
void RefuseRemoteInRealtime(const Scenario& scenario, const RunOptions& options) {
  if (!options.listen.empty() && !scenario.lockstep()) {
    throw Error(
        "--remote network needs lockstep pacing (--pacing lockstep): in realtime the bridge "
        "asks its medium for the next event at every frame, a network round trip each");
  }
}

// `sitlnet run` with every robot on this host: the run's stages (runner/run_stages.h).
class OneHostRun final : public CentralStages {
 public:
  using CentralStages::CentralStages;

 protected:
  void Refuse() override {
    RefuseRemoteInRealtime(scenario_, options_);
    GcsEndpointsOf(options_.gcs);  // A bad --gcs is refused before anything is created.
  }
  void PrepareHost() override { PrepareRobotHost(scenario_, scenario_.robots.size()); }
  bool Open(int stop_fd) override {
    MakeRunFolder(report_.run_dir);
    WriteEffectiveScenario(scenario_, report_.run_dir);
    return AcceptRemoteMedium(scenario_, options_, stop_fd, &remote_medium_, &report_);
  }
  // Namespaces, physics, medium, images, torn down in reverse when this goes; then the physics
  // side that records trajectories.csv.
  void SetUp() override {
    setup_ =
        std::make_unique<RunSetup>(scenario_, options_, report_.run_dir, std::move(remote_medium_));
    physics_ = std::make_unique<LocalPhysics>(setup_.get(), options_, report_.run_dir);
  }
  RunParts& parts() override { return *setup_; }
  RunPhysics& physics() override { return *physics_; }
  void Stop() override {
    StopRobots(&setup_->robots(), &setup_->clock_publishers(), &report_);
    report_.stop_ns = MonotonicNowNs() - loop_.end_ns;
    report_.gcs_relay = StopGcsRelay(setup_->gcs_relay());
    // Every image is reaped by now and nothing else was a child yet (gnuplot
    // runs later), so the children's usage is the robots'.
    report_.robots_cpu_s = CpuSeconds(RUSAGE_CHILDREN);
    setup_->medium_records().Flush();
  }

 private:
  std::unique_ptr<network_side::RemoteMedium> remote_medium_;  // Until the setup takes it.
  std::unique_ptr<RunSetup> setup_;
  std::unique_ptr<LocalPhysics> physics_;  // Destroyed before the setup.
};

}  // namespace

// The scenario with the command line's overrides applied, revalidated.
Scenario ApplyRunOverrides(const Scenario& scenario, const RunOptions& options) {
  proto::Scenario spec = scenario.spec;
  if (options.duration_s) {
    if (!(*options.duration_s > 0 && *options.duration_s <= kMaxDurationMs / 1000)) {
      throw Error("--duration must be in (0, " + std::to_string(kMaxDurationMs / 1000) +
                  "] seconds (a year)");
    }
    spec.mutable_timing()->set_duration_ms(static_cast<int64_t>(*options.duration_s * 1000));
  }
  if (options.pacing) spec.mutable_timing()->set_pacing(ProtoPacing(*options.pacing));
  if (options.seed) spec.mutable_timing()->set_seed(*options.seed);
  if (options.no_shadowing) spec.mutable_radio()->set_shadowing(false);
  Scenario effective =
      ValidateScenarioSpec(std::move(spec), scenario.source_path + " (with overrides)");
  effective.source_path = scenario.source_path;
  return effective;
}

RunReport RunScenario(const RunOptions& options) {
  const TimeNs begin_ns = MonotonicNowNs();
  const Scenario scenario = LoadWithOverrides(options);
  RunReport report;
  report.run_dir = options.out_dir.empty() ? DefaultRunDir(scenario.name) : options.out_dir;
  report.files_before = ListRunFolderFiles(report.run_dir);
  // The robots on node hosts: this host runs the medium and the coordinator only.
  if (RunsOnNodeHosts(scenario, options)) {
    return RunOnNodeHosts(scenario, options, std::move(report), begin_ns);
  }
  OneHostRun run(scenario, options, std::move(report), begin_ns);
  run.Run();
  return run.TakeReport();
}

}  // namespace sitlnet::runner

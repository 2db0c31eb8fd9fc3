#include "runner/run_setup.h"

#include <cstdio>

#include "nns/nns.h"
#include "runner/physics_options.h"
#include "runner/robot_start.h"

namespace sitlnet::runner {

// Brings the scenario up (registering this process as its run: another run of it is refused,
// not torn down) and tears it down however the run ends.
class ScenarioNamespaces {
 public:
  explicit ScenarioNamespaces(const Scenario& scenario) : name_(scenario.name) {
    nns::UpOptions up_options;
    up_options.register_caller_as_run = true;
    nns::Up(scenario, up_options);
  }
  ~ScenarioNamespaces() {
    try {
      nns::Down(name_);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "sitlnet run: down %s: %s\n", name_.c_str(), error.what());
    }
  }
  ScenarioNamespaces(const ScenarioNamespaces&) = delete;
  ScenarioNamespaces& operator=(const ScenarioNamespaces&) = delete;

 private:
  std::string name_;
};

RunSetup::RunSetup(const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
                   std::unique_ptr<network_side::RemoteMedium> remote)
    : scenario_(scenario),
      options_(options),
      run_dir_(run_dir),
      lockstep_(scenario.spec.timing().pacing() == proto::Timing::PACING_LOCKSTEP),
      remote_owned_(std::move(remote)),
      run_timebase_(scenario.spec.timing().realtime_factor()) {
  BringUpNamespaces();
  StartPhysics();
  StartMedium();
  StartRobots();
}

RunSetup::~RunSetup() = default;

void RunSetup::BringUpNamespaces() {
  namespaces_ = std::make_unique<ScenarioNamespaces>(scenario_);
  std::fprintf(stderr,
               "sitlnet run: %s: %zu robots up, starting medium, physics and images -> %s\n",
               scenario_.name.c_str(), scenario_.robots.size(), run_dir_.c_str());
}

void RunSetup::StartPhysics() {
  // Realtime pacing on a busy host: a normal-priority loop waits milliseconds for a core
  // (docs/performance.md, "Realtime 64"). Before the physics and bridge threads exist, so that
  // they inherit it; children (images, gnuplot) reset to normal scheduling.
  if (!lockstep_ && options_.realtime_priority > 0) {
    if (const std::string refused = RequestRealtimePriority(options_.realtime_priority);
        !refused.empty()) {
      std::fprintf(stderr, "sitlnet run: warning: %s\n", refused.c_str());
    }
  }
  // Its sockets in the scenario's ctl namespace, where the robots' ctl0 links end: no one else
  // can bind their ports there (nns.h, CtlNetnsName).
  physics::ServerOptions physics_options = PhysicsOptionsFromEnvironment();
  physics_options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario_.name));
  // The autopilots' pacing: in lockstep the frame gate (silent after the scenario's timeout),
  // in realtime the run's timebase (the coordinator begins it before iteration 0).
  if (lockstep_) {
    physics_options.periodic_states = false;  // one state per iteration, from the gate
    physics_options.frame_gate_timeout_ns = scenario_.spec.silent_robot_timeout_ms() * kNsPerMs;
  } else {
    physics_options.autopilot_wall_clock = &run_timebase_;
  }
  physics_server_ = std::make_unique<physics::PhysicsServer>(scenario_, physics_options);
}

void RunSetup::StartMedium() {
  tapbridge::BridgeOptions bridge_options;
  bridge_options.seed = scenario_.spec.timing().seed();
  std::unique_ptr<tapbridge::MediumModel> medium;
  if (remote_owned_) {
    remote_medium_ = remote_owned_.get();
    medium = std::move(remote_owned_);
  } else {
    medium = tapbridge::MakeMacPhySimMedium(scenario_);
    if (options_.record_losses) {
      loss_log_ = MakeLossLog(run_dir_, scenario_);
      loss_log_->SetLiveSink(options_.live);
      medium->SetTraceSink([log = loss_log_.get()](const mac::TraceEvent& e) { log->Add(e); });
    }
  }
  bridge_ = std::make_unique<tapbridge::BridgeCore>(scenario_, std::move(medium), bridge_options);
  bridge_->AttachAll();
  medium_records_ = std::make_unique<MediumRecords>(
      run_dir_, static_cast<int>(scenario_.robots.size()), lockstep_, loss_log_.get());
  medium_records_->connectivity().SetLiveSink(options_.live);
  medium_records_->Attach(bridge_.get());
}

void RunSetup::StartRobots() {
  robots_ = StartImages(scenario_, options_, run_dir_);
  if (scenario_.spec.timing().ros2_clock_hz() > 0) {
    shared_time_.emplace(ros2_clock::SharedVirtualTime::Create());
    clock_publishers_ = StartClockPublishers(scenario_, options_, run_dir_, *shared_time_);
  }
  // Realtime with wait_for_robots too: the clock starts once the images have booted
  // (docs/performance.md, "Where the realtime bursts come from").
  if (lockstep_ || scenario_.spec.timing().wait_for_robots()) {
    WaitForRobotsToSpeak(scenario_, robots_, physics_server_.get(),
                         lockstep_ ? "lockstep" : "wait_for_robots");
    // Readiness is timed from the clock's start: an image that spoke early may have waited
    // for the slowest one longer than its ready_timeout_ms.
    for (RobotSlot& robot : robots_) robot.started_wall_ns = MonotonicNowNs();
  }
}

}  // namespace sitlnet::runner

#include "runner/coordinated_run.h"

#include <sys/resource.h>

#include "runner/cpu_time.h"

namespace sitlnet::runner {
namespace {

// The network side's observers, in the order they are told: the supervisor first (a robot that
// exited is counted out on the same progress line), then the progress line, then the relay's clock
// and its report to the live view.
std::vector<IterationObserver*> NetworkObservers(RobotSupervisor* supervisor,
                                                 ProgressLine* progress, GcsRelayClock* gcs_clock,
                                                 GcsRelayLive* gcs_live) {
  std::vector<IterationObserver*> observers = {supervisor, progress};
  if (gcs_clock != nullptr) observers.push_back(gcs_clock);
  if (gcs_live != nullptr) observers.push_back(gcs_live);
  return observers;
}

}  // namespace

CoordinatedRun::CoordinatedRun(RunParts* setup, RunPhysics* physics, const RunOptions& options,
                               const std::string& run_dir, int interrupt_fd)
    : physics_(*physics),
      bridge_sim_(setup->scenario(), &setup->bridge(), setup->scenario().pacing(),
                  setup->scenario().spec.timing().realtime_factor()),
      progress_(options.progress, &setup->bridge(), &setup->robots(), setup->scenario().duration_ns,
                setup->gcs_relay(), setup->local_physics(),
                setup->scenario().pacing() == clock::Pacing::kRealtime),
      supervisor_(&setup->robots(),
                  setup->scenario().spec.on_robot_failure() == proto::Scenario::ROBOT_FAILURE_STOP,
                  &progress_, options.program),
      gcs_clock_(setup->gcs_relay()
                     ? std::make_unique<GcsRelayClock>(setup->gcs_relay(), &setup->run_timebase(),
                                                       setup->lockstep())
                     : nullptr),
      gcs_live_(
          setup->gcs_relay() && options.live != nullptr
              ? std::make_unique<GcsRelayLive>(&setup->scenario(), setup->gcs_relay(), options.live)
              : nullptr),
      observed_network_(&bridge_sim_, NetworkObservers(&supervisor_, &progress_, gcs_clock_.get(),
                                                       gcs_live_.get())),
      // The bridge is single-threaded: always the coordinator's own thread.
      network_(coordinator::MakeInProcessConnector("network", coordinator::Role::kNetwork,
                                                   &observed_network_,
                                                   coordinator::Threading::kCallerThread)),
      run_options_(coordinator::OptionsFromScenario(setup->scenario())),
      metrics_csv_(run_dir + "/metrics.csv"),
      live_(options.live) {
  run_options_.timebase_out = &setup->run_timebase();
  run_options_.metrics_csv = &metrics_csv_;
  run_options_.metrics = &metrics_;
  run_options_.on_iteration = [this](const coordinator::IterationMetrics& m) {
    progress_.IterationLag(m.lag_ns);
    if (live_ == nullptr) return;
    // Once per simulated second, not per iteration.
    if (auto second = live_timing_.Add(m.start_ns, m.stf, m.lag_ns)) live_->Timing(*second);
  };
  run_options_.interrupt_fd = interrupt_fd;
  run_options_.lockstep_robots = setup->lockstep();
}

LoopOutcome CoordinatedRun::Run() {
  LoopOutcome outcome;
  outcome.begin_ns = MonotonicNowNs();
  try {
    outcome.result = coordinator::RunCoordinator(physics_.connector(), *network_, run_options_);
  } catch (const Error& error) {
    outcome.failure = error.what();
  }
  outcome.end_ns = MonotonicNowNs();
  outcome.self_cpu_s = CpuSeconds(RUSAGE_SELF);
  progress_.Finish();
  if (live_ != nullptr) {
    if (auto second = live_timing_.Finish()) live_->Timing(*second);
  }
  metrics_csv_.Flush();
  physics_.Flush();
  outcome.closest_approach = physics_.closest_approach();
  outcome.metrics = metrics_.Summarize();
  return outcome;
}

}  // namespace sitlnet::runner

// The run stage of `sitlnet run`: the coordinator steps the physics side (here or on node hosts,
// recording trajectories.csv) and the network side, whose iterations the robot supervisor and the
// progress line observe; metrics.csv is written as it goes.
#ifndef SITLNET_RUNNER_COORDINATED_RUN_H_
#define SITLNET_RUNNER_COORDINATED_RUN_H_

#include <memory>
#include <string>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"
#include "run_formats/run_formats.h"
#include "runner/gcs_relay_stage.h"
#include "runner/progress_line.h"
#include "runner/robot_supervisor.h"
#include "runner/run_parts.h"
#include "runner/runner.h"

namespace sitlnet::runner {

// What the coordinator's loop came to.
struct LoopOutcome {
  coordinator::RunResult result;
  std::string failure;  // The Error that ended the run; empty if none.
  coordinator::MetricsSummary metrics;
  TimeNs begin_ns = 0;  // Monotonic instants of the loop's start and end.
  TimeNs end_ns = 0;
  double self_cpu_s = 0;  // user+sys of this process (all threads) at the loop's end.
  std::optional<run_formats::ClosestApproach> closest_approach;  // Over trajectories.csv's samples.
};

class CoordinatedRun {
 public:
  // Creates metrics.csv (throws Error naming the file). `setup` and `physics` must outlive this;
  // `interrupt_fd`: the run's StopSignal.
  CoordinatedRun(RunParts* setup, RunPhysics* physics, const RunOptions& options,
                 const std::string& run_dir, int interrupt_fd);
  // Runs every iteration (or until interrupted, or until a connector fails: the Error is the
  // outcome's failure, not thrown), then ends the progress line and flushes metrics.csv and
  // trajectories.csv (throws Error naming the file that cannot be written).
  LoopOutcome Run();

 private:
  RunPhysics& physics_;
  network_side::BridgeSimulator bridge_sim_;
  ProgressLine progress_;
  RobotSupervisor supervisor_;
  std::unique_ptr<GcsRelayClock> gcs_clock_;  // Null without a GCS relay.
  std::unique_ptr<GcsRelayLive> gcs_live_;    // Null without a GCS relay or a live view.
  ObservedSimulator observed_network_;
  std::unique_ptr<coordinator::Connector> network_;
  coordinator::CoordinatorOptions run_options_;
  coordinator::MetricsCsvWriter metrics_csv_;
  coordinator::MetricsCollector metrics_;
  run_formats::LiveSink* live_;                       // May be null.
  run_formats::SecondTimingAccumulator live_timing_;  // For live_, on the coordinator's thread.
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_COORDINATED_RUN_H_

// The stages a central host shares, whether every robot runs here (runner/run.cc) or on node
// hosts (runner/fleet_run.cc): the coordinator's loop over the parts set up, and the report.
#ifndef SITLNET_RUNNER_CENTRAL_STAGES_H_
#define SITLNET_RUNNER_CENTRAL_STAGES_H_

#include "runner/coordinated_run.h"
#include "runner/run_parts.h"
#include "runner/run_stages.h"
#include "runner/runner.h"

namespace sitlnet::runner {

class CentralStages : public RunStages {
 public:
  // `report` holds the run folder; `begin_ns`: the run's start (RunScenario's). `scenario` and
  // `options` must outlive this.
  CentralStages(const Scenario& scenario, const RunOptions& options, RunReport report,
                TimeNs begin_ns)
      : scenario_(scenario), options_(options), report_(std::move(report)), begin_ns_(begin_ns) {}
  RunReport TakeReport() { return std::move(report_); }

 protected:
  // What SetUp brought up: the run's parts and its physics side.
  virtual RunParts& parts() = 0;
  virtual RunPhysics& physics() = 0;

  // The coordinator's iterations, the robots supervised (CoordinatedRun); the phases' times in
  // the report.
  bool Loop(int stop_fd) override;
  // The exit code, the failure line, summary.json and the plots (ReportRun).
  void Report() override;

  const Scenario& scenario_;
  const RunOptions& options_;
  RunReport report_;
  LoopOutcome loop_;

 private:
  const TimeNs begin_ns_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_CENTRAL_STAGES_H_

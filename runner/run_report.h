// The report stage of `sitlnet run`: the run's exit code and failure line, the remote medium
// link's figures, connectivity.csv, summary.json and the plots.
#ifndef SITLNET_RUNNER_RUN_REPORT_H_
#define SITLNET_RUNNER_RUN_REPORT_H_

#include "runner/coordinated_run.h"
#include "runner/run_parts.h"
#include "runner/runner.h"

namespace sitlnet::runner {

// Sets report->exit_code (0 done, 1 failed, 130 interrupted) and interrupted from `loop`, prints
// its failure, writes the summary and plots, and tells a remote medium the run is over. The
// robots are stopped by then (their usage is in the summary).
void ReportRun(RunParts& setup, const LoopOutcome& loop, RunReport* report);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_REPORT_H_

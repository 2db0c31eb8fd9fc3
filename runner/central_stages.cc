#include "runner/central_stages.h"

#include "runner/run_report.h"

namespace sitlnet::runner {

bool CentralStages::Loop(int stop_fd) {
  CoordinatedRun run(&parts(), &physics(), options_, report_.run_dir, stop_fd);
  loop_ = run.Run();
  report_.startup_ns = loop_.begin_ns - begin_ns_;
  report_.loop_ns = loop_.end_ns - loop_.begin_ns;
  report_.self_cpu_s = loop_.self_cpu_s;
  return true;
}

void CentralStages::Report() { ReportRun(parts(), loop_, &report_); }

}  // namespace sitlnet::runner

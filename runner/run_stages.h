// The stage list of a run process, said once: `sitlnet run` on one host (runner/run.cc), a
// fleet's central host (runner/fleet_run.cc) and a node host (runner/node_run.cc) each fill in
// their parts of it. A new stage is added here, with a default that does nothing.
#ifndef SITLNET_RUNNER_RUN_STAGES_H_
#define SITLNET_RUNNER_RUN_STAGES_H_

#include <optional>

#include "common/common.h"

namespace sitlnet::runner {

class RunStages {
 public:
  // The parts brought up by SetUp are torn down when the derived object goes, before the
  // StopSignal this base holds: a Ctrl-C during teardown still stops in order.
  virtual ~RunStages() = default;

  // Runs the stages in this order:
  //   1. Refuse: bad input, before anything exists.
  //   2. PrepareHost: what the host must grant (privileges, open files).
  //   3. (here) the StopSignal: Ctrl-C from here on stops in order.
  //   4. Open: the run folder, and the peers this process waits for before it sets up.
  //   5. SetUp: namespaces, physics, medium, relay, images; ready for iteration 0.
  //   6. Loop: the iterations (the coordinator's, or served for the central's).
  //   7. Stop: the robots and the relay stopped, the records flushed.
  //   8. Report: the exit code, summary.json and the plots.
  // Open and Loop return false when the run ends there (interrupted, or a failure they
  // reported): the later stages are skipped. Throws what a stage throws.
  void Run();

 protected:
  virtual void Refuse() {}
  virtual void PrepareHost() {}
  virtual bool Open(int stop_fd) = 0;
  virtual void SetUp() = 0;
  virtual bool Loop(int stop_fd) = 0;
  virtual void Stop() {}
  virtual void Report() {}

 private:
  std::optional<StopSignal> stop_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_STAGES_H_

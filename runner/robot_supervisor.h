// Supervision of the robots' images during a run: exits, readiness, restart policy and the
// scenario's on_robot_failure policy.
#ifndef SITLNET_RUNNER_ROBOT_SUPERVISOR_H_
#define SITLNET_RUNNER_ROBOT_SUPERVISOR_H_

#include <string>
#include <vector>

#include "common/common.h"
#include "runner/iteration_observer.h"
#include "runner/progress_line.h"
#include "runner/robot_slot.h"

namespace sitlnet::runner {

// After each iteration: notes each image that exited (at the iteration's end time), checks
// readiness (log files read twice a second at most), restarts a failed image by its manifest's
// policy, or reports it and, with `stop_on_failure`, stops the run (throws Error naming the
// robot and its log).
class RobotSupervisor final : public IterationObserver {
 public:
  // `progress` (may be null) is ended before each line this prints. Both must outlive this.
  // `program` begins those lines ("sitlnet run", "sitlnet node").
  RobotSupervisor(std::vector<RobotSlot>* robots, bool stop_on_failure, ProgressLine* progress,
                  std::string program);
  void IterationEnded(const proto::coord::Start& start) override { CheckRobots(start.end_ns()); }

 private:
  void CheckRobots(TimeNs now_ns);
  void CheckReadiness(RobotSlot& robot, TimeNs now_ns);
  // A robot's image failed: restart it by its manifest's policy, or report
  // it (and stop the run if the scenario says so).
  void HandleFailure(RobotSlot& robot, const std::string& what);
  void EndProgressLine();

  std::vector<RobotSlot>& robots_;
  bool stop_on_failure_;
  ProgressLine* progress_;
  std::string program_;
  TimeNs next_ready_check_wall_ns_ = 0;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ROBOT_SUPERVISOR_H_

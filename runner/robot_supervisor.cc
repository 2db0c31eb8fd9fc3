#include "runner/robot_supervisor.h"

#include <cstdio>

namespace sitlnet::runner {

RobotSupervisor::RobotSupervisor(std::vector<RobotSlot>* robots, bool stop_on_failure,
                                 ProgressLine* progress, std::string program)
    : robots_(*robots),
      stop_on_failure_(stop_on_failure),
      progress_(progress),
      program_(std::move(program)) {}

void RobotSupervisor::EndProgressLine() {
  if (progress_ != nullptr) progress_->Finish();
}

void RobotSupervisor::CheckRobots(TimeNs now_ns) {
  // Log files are read for readiness twice a second at most.
  const bool check_ready = MonotonicNowNs() >= next_ready_check_wall_ns_;
  if (check_ready) next_ready_check_wall_ns_ = MonotonicNowNs() + kNsPerS / 2;
  for (RobotSlot& robot : robots_) {
    if (!robot.process || robot.exit_status) continue;
    if (check_ready && !robot.ready) CheckReadiness(robot, now_ns);
    if (robot.exit_status) continue;
    robot.exit_status = robot.process->PollExit();
    if (!robot.exit_status) continue;
    robot.exited_at_ns = now_ns;
    // What it left running (a daemon it forked) ends with it, restarted or not.
    if (robot.cgroup) robot.cgroup->KillAll();
    const int status = *robot.exit_status;
    EndProgressLine();
    std::fprintf(stderr, "%s: robot \"%s\" exited with status %d at t=%.2f s (log: %s)\n",
                 program_.c_str(), robot.name.c_str(), status,
                 static_cast<double>(now_ns) / kNsPerS, robot.process->log_path().c_str());
    if (status != 0) HandleFailure(robot, "failed with status " + std::to_string(status));
  }
}

void RobotSupervisor::CheckReadiness(RobotSlot& robot, TimeNs now_ns) {
  if (robot.process->IsReady()) {
    robot.ready = true;
    return;
  }
  const TimeNs timeout_ns = robot.image.manifest.ready_timeout_ms() * kNsPerMs;
  if (MonotonicNowNs() - robot.started_wall_ns < timeout_ns) return;
  EndProgressLine();
  const std::string what = "not ready within " +
                           std::to_string(robot.image.manifest.ready_timeout_ms()) + " ms (no \"" +
                           robot.image.manifest.ready_log_line() + "\" in its log)";
  std::fprintf(stderr, "%s: robot \"%s\" %s (log: %s)\n", program_.c_str(), robot.name.c_str(),
               what.c_str(), robot.process->log_path().c_str());
  robot.process->Stop();
  robot.exit_status = robot.process->PollExit();
  HandleFailure(robot, what);
}

void RobotSupervisor::HandleFailure(RobotSlot& robot, const std::string& what) {
  const auto& manifest = robot.image.manifest;
  if (manifest.restart() == proto::ImageManifest::RESTART_ON_FAILURE &&
      robot.restarts < manifest.max_restarts()) {
    ++robot.restarts;
    std::fprintf(stderr, "%s: restarting robot \"%s\" (%u of at most %u)\n", program_.c_str(),
                 robot.name.c_str(), robot.restarts, manifest.max_restarts());
    const std::string log_path = robot.process->log_path();
    robot.process.reset();  // reaped already; stops it if not
    // What the failed image left behind (a daemon it forked) goes with it, not into the restart.
    if (robot.cgroup) robot.cgroup->KillAll();
    robot.process = std::make_unique<images::RobotProcess>(robot.image, robot.context,
                                                           robot.sitlnet_exe, log_path);
    robot.exit_status.reset();
    robot.started_wall_ns = MonotonicNowNs();
    robot.ready = false;
    return;
  }
  if (stop_on_failure_) {
    throw Error("robot \"" + robot.name + "\" " + what +
                " (on_robot_failure: ROBOT_FAILURE_STOP; log: " + robot.process->log_path() + ")");
  }
}

}  // namespace sitlnet::runner

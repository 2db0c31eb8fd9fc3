#include "runner/run_monitor.h"

#include <unistd.h>

#include <cstdio>

#include "runner/outputs.h"

namespace sitlnet::runner {

RecordingPhysics::RecordingPhysics(coordinator::Simulator* inner, const physics::World* world,
                                   const physics::GeodeticFrame& frame, const std::string& csv_path,
                                   TimeNs period_ns)
    : inner_(*inner),
      world_(*world),
      frame_(frame),
      csv_(csv_path, kTrajectoryHeader),
      period_ns_(period_ns) {}

void RecordingPhysics::Record(TimeNs time_ns) {
  for (int i = 0; i < world_.robot_count(); ++i) {
    const physics::RobotPose pose = world_.Pose(i);
    PoseRow row;
    row.time_ns = time_ns;
    row.robot = i;
    row.x_m = pose.position_m.x;
    row.y_m = pose.position_m.y;
    row.z_m = pose.position_m.z;
    row.qw = pose.orientation.w;
    row.qx = pose.orientation.x;
    row.qy = pose.orientation.y;
    row.qz = pose.orientation.z;
    row.vx_m_s = pose.velocity_m_s.x;
    row.vy_m_s = pose.velocity_m_s.y;
    row.vz_m_s = pose.velocity_m_s.z;
    const physics::GeodeticPoint where = frame_.ToGeodetic(pose.position_m);
    row.latitude_deg = where.latitude_deg;
    row.longitude_deg = where.longitude_deg;
    row.altitude_m = where.altitude_m;
    csv_.Append(FormatPoseRow(row));
  }
}

void RecordingPhysics::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                    coordinator::IterationContext& context) {
  if (start.start_ns() == 0) Record(0);
  inner_.RunIteration(start, end, context);
  if (shared_time_ != nullptr) shared_time_->Store(start.end_ns());
  if (start.end_ns() >= next_sample_ns_ + period_ns_) {
    Record(start.end_ns());
    next_sample_ns_ = start.end_ns();
  }
}

MonitoringNetwork::MonitoringNetwork(coordinator::Simulator* inner, tapbridge::BridgeCore* bridge,
                                     std::vector<RobotSlot>* robots, bool stop_on_failure,
                                     bool progress, TimeNs duration_ns)
    : inner_(*inner),
      bridge_(*bridge),
      robots_(*robots),
      stop_on_failure_(stop_on_failure),
      progress_(progress),
      duration_ns_(duration_ns) {}

void MonitoringNetwork::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                     coordinator::IterationContext& context) {
  if (wall_start_ns_ == 0) wall_start_ns_ = MonotonicNowNs();
  inner_.RunIteration(start, end, context);
  CheckRobots(start.end_ns());
  if (progress_ && MonotonicNowNs() >= next_print_wall_ns_) {
    PrintProgress(start.end_ns());
    // A terminal gets one line redrawn twice a second; a log file a line
    // every 5 s.
    next_print_wall_ns_ = MonotonicNowNs() + (isatty(STDERR_FILENO) ? kNsPerS / 2 : 5 * kNsPerS);
  }
}

void MonitoringNetwork::CheckRobots(TimeNs now_ns) {
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
    FinishProgress();
    std::fprintf(stderr, "sitlnet run: robot \"%s\" exited with status %d at t=%.2f s (log: %s)\n",
                 robot.name.c_str(), status, static_cast<double>(now_ns) / kNsPerS,
                 robot.process->log_path().c_str());
    if (status != 0) HandleFailure(robot, "failed with status " + std::to_string(status), now_ns);
  }
}

void MonitoringNetwork::CheckReadiness(RobotSlot& robot, TimeNs now_ns) {
  if (robot.process->IsReady()) {
    robot.ready = true;
    return;
  }
  const TimeNs timeout_ns = robot.image.manifest.ready_timeout_ms() * kNsPerMs;
  if (MonotonicNowNs() - robot.started_wall_ns < timeout_ns) return;
  FinishProgress();
  const std::string what = "not ready within " +
                           std::to_string(robot.image.manifest.ready_timeout_ms()) + " ms (no \"" +
                           robot.image.manifest.ready_log_line() + "\" in its log)";
  std::fprintf(stderr, "sitlnet run: robot \"%s\" %s (log: %s)\n", robot.name.c_str(), what.c_str(),
               robot.process->log_path().c_str());
  robot.process->Stop();
  robot.exit_status = robot.process->PollExit();
  HandleFailure(robot, what, now_ns);
}

void MonitoringNetwork::HandleFailure(RobotSlot& robot, const std::string& what, TimeNs now_ns) {
  const auto& manifest = robot.image.manifest;
  if (manifest.restart() == proto::ImageManifest::RESTART_ON_FAILURE &&
      robot.restarts < manifest.max_restarts()) {
    ++robot.restarts;
    std::fprintf(stderr, "sitlnet run: restarting robot \"%s\" (%u of at most %u)\n",
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

void MonitoringNetwork::PrintProgress(TimeNs now_ns) {
  uint64_t sent = 0, delivered = 0, lost = 0;
  for (int i = 0; i < bridge_.robot_count(); ++i) {
    const tapbridge::MediumCounters counters = bridge_.medium_counters(i);
    sent += counters.sent;
    delivered += counters.delivered;
    lost += counters.queue_drops;
    for (const auto& [reason, count] : counters.lost) lost += count;
  }
  int alive = 0, with_image = 0;
  for (const RobotSlot& robot : robots_) {
    if (!robot.process) continue;
    ++with_image;
    if (!robot.exit_status) ++alive;
  }
  const double wall_s = static_cast<double>(MonotonicNowNs() - wall_start_ns_) / kNsPerS;
  const double sim_s = static_cast<double>(now_ns) / kNsPerS;
  std::fprintf(stderr, isatty(STDERR_FILENO) ? "\r" : "");
  std::fprintf(stderr,
               "t=%7.2f/%.0f s  x%.2f real time  robots %d/%d  frames sent %llu delivered "
               "%llu lost %llu   ",
               sim_s, static_cast<double>(duration_ns_) / kNsPerS,
               wall_s > 0 ? sim_s / wall_s : 0.0, alive, with_image,
               static_cast<unsigned long long>(sent), static_cast<unsigned long long>(delivered),
               static_cast<unsigned long long>(lost));
  if (!isatty(STDERR_FILENO)) std::fputc('\n', stderr);
  printed_ = isatty(STDERR_FILENO);
}

void MonitoringNetwork::FinishProgress() {
  if (printed_) std::fputc('\n', stderr);
  printed_ = false;
}

}  // namespace sitlnet::runner

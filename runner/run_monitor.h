// Decorators of the run's two simulators: the physics side records
// trajectories; the network side supervises robot processes, logs
// deliveries and prints the live progress line. Both run on their
// connector's thread, so each touches only its own simulator.
#ifndef SITLNET_RUNNER_RUN_MONITOR_H_
#define SITLNET_RUNNER_RUN_MONITOR_H_

#include <memory>
#include <string>
#include <vector>

#include "coordinator/connector.h"
#include "nns/nns.h"
#include "physics_mujoco/physics_mujoco.h"
#include "robot_images/robot_images.h"
#include "ros2_clock/ros2_clock.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

// Physics simulator + trajectories.csv every `period_ns` of virtual time.
class RecordingPhysics final : public coordinator::Simulator {
 public:
  // `frame`: the scenario's geodetic frame, for the rows' latitude, longitude and altitude.
  RecordingPhysics(coordinator::Simulator* inner, const physics::World* world,
                   const physics::GeodeticFrame& frame, const std::string& csv_path,
                   TimeNs period_ns);
  proto::coord::Poses InitialPoses() override { return inner_.InitialPoses(); }
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;
  // Each iteration's end time, once the physics has reached it, goes there too (the robots'
  // /clock publishers read it).
  void ShareTimeWith(ros2_clock::SharedVirtualTime* shared) { shared_time_ = shared; }
  void Flush() { csv_.Flush(); }

 private:
  void Record(TimeNs time_ns);
  coordinator::Simulator& inner_;
  const physics::World& world_;
  physics::GeodeticFrame frame_;
  LineFile csv_;
  TimeNs period_ns_;
  TimeNs next_sample_ns_ = 0;
  ros2_clock::SharedVirtualTime* shared_time_ = nullptr;
};

// A robot image's process and what became of it.
struct RobotSlot {
  std::string name;
  // A container image's registration for `down` (docs/containers.md); outlives `process`.
  std::unique_ptr<nns::ContainerRegistration> container;
  // The image's cgroup (host programs); outlives `process`. Null: none (no image, a container
  // image, or the host offers none).
  std::unique_ptr<nns::RobotCgroup> cgroup;
  std::optional<nns::CgroupUsage> usage;          // Read once its processes are gone.
  std::unique_ptr<images::RobotProcess> process;  // Null: no image.
  std::optional<int> exit_status;
  TimeNs exited_at_ns = 0;  // Virtual time the exit was noticed.
  // What it takes to start the image again (restart policy).
  images::Image image;
  images::LaunchContext context;
  std::string sitlnet_exe;
  uint32_t restarts = 0;
  TimeNs started_wall_ns = 0;  // For the readiness timeout.
  bool ready = false;
};

// Network simulator + robot supervision + progress line.
class MonitoringNetwork final : public coordinator::Simulator {
 public:
  MonitoringNetwork(coordinator::Simulator* inner, tapbridge::BridgeCore* bridge,
                    std::vector<RobotSlot>* robots, bool stop_on_failure, bool progress,
                    TimeNs duration_ns);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;
  // Ends the progress line (a newline if one was printed).
  void FinishProgress();

 private:
  void CheckRobots(TimeNs now_ns);
  // A robot's image failed: restart it by its manifest's policy, or report
  // it (and stop the run if the scenario says so).
  void HandleFailure(RobotSlot& robot, const std::string& what, TimeNs now_ns);
  void CheckReadiness(RobotSlot& robot, TimeNs now_ns);
  TimeNs next_ready_check_wall_ns_ = 0;
  void PrintProgress(TimeNs now_ns);

  coordinator::Simulator& inner_;
  tapbridge::BridgeCore& bridge_;
  std::vector<RobotSlot>& robots_;
  bool stop_on_failure_;
  bool progress_;
  TimeNs duration_ns_;
  TimeNs wall_start_ns_ = 0;
  TimeNs next_print_wall_ns_ = 0;
  bool printed_ = false;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_MONITOR_H_

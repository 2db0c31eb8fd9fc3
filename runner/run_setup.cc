#include "runner/run_setup.h"

#include <cstdio>

#include "runner/gcs_relay_stage.h"
#include "runner/physics_options.h"
#include "runner/robot_host.h"
#include "runner/robot_start.h"

namespace sitlnet::runner {

RunSetup::RunSetup(const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
                   std::unique_ptr<network_side::RemoteMedium> remote)
    : scenario_(scenario),
      options_(options),
      run_dir_(run_dir),
      lockstep_(scenario.lockstep()),
      remote_owned_(std::move(remote)),
      run_timebase_(scenario.spec.timing().realtime_factor()) {
  BringUpNamespaces();
  StartPhysics();
  StartMedium();
  StartGcsRelay();
  StartRobots();
}

RunSetup::~RunSetup() = default;

void RunSetup::BringUpNamespaces() {
  namespaces_ = std::make_unique<ScenarioNamespaces>(scenario_);
  std::fprintf(stderr,
               "sitlnet run: %s: %zu robots up, starting medium, physics and images -> %s\n",
               scenario_.name.c_str(), scenario_.robots.size(), run_dir_.c_str());
}

void RunSetup::StartPhysics() {
  if (!lockstep_) RequestRealtimeRunPriority(options_.realtime_priority, "sitlnet run");
  physics_server_ = std::make_unique<physics::PhysicsServer>(
      scenario_, RunPhysicsOptions(scenario_, lockstep_, &run_timebase_));
}

void RunSetup::StartMedium() {
  medium_ = std::make_unique<RunMedium>(scenario_, options_, run_dir_, std::move(remote_owned_));
}

void RunSetup::StartGcsRelay() {
  gcs_relay_ = runner::StartGcsRelay(scenario_, GcsEndpointsOf(options_.gcs), run_dir_);
}

void RunSetup::StartRobots() {
  robots_ = StartImages(scenario_, options_, run_dir_);
  if (scenario_.spec.timing().ros2_clock_hz() > 0) {
    shared_time_.emplace(ros2_clock::SharedVirtualTime::Create());
    clock_publishers_ = StartClockPublishers(scenario_, options_, run_dir_, *shared_time_);
  }
  // Realtime with wait_for_robots too: the clock starts once the images have booted
  // (docs/performance.md, "Where the realtime bursts come from").
  if (lockstep_ || scenario_.spec.timing().wait_for_robots()) {
    WaitForRobotsToSpeak(scenario_, robots_, physics_server_.get(),
                         lockstep_ ? "lockstep" : "wait_for_robots");
    // Readiness is timed from the clock's start: an image that spoke early may have waited
    // for the slowest one longer than its ready_timeout_ms.
    for (RobotSlot& robot : robots_) robot.started_wall_ns = MonotonicNowNs();
  }
}

}  // namespace sitlnet::runner

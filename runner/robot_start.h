// Starting the robots' software for a run: each robot's image, its /clock publisher, and the
// wait until every image has spoken to physics.
#ifndef SITLNET_RUNNER_ROBOT_START_H_
#define SITLNET_RUNNER_ROBOT_START_H_

#include <memory>
#include <string>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "robot_images/robot_images.h"
#include "ros2_clock/ros2_clock.h"
#include "runner/robot_slot.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// Starts the image of every robot of `robots` (empty: of all; one slot per robot of the scenario,
// indexed as its robots; a robot without an image, or not of `robots`, has no process); throws
// Error naming the robot and its log if one cannot start or exits at once.
std::vector<RobotSlot> StartImages(const Scenario& scenario, const RunOptions& options,
                                   const std::string& run_dir, const std::vector<int>& robots = {});

// Timing.ros2_clock_hz > 0: one /clock publisher per robot (ros2_clock/), started like an image
// (sandboxed, in the robot's namespace, log <run>/robots/<robot>.ros2_clock.log) and handed the
// run's shared virtual time as descriptor images::kPassedFd.
std::vector<std::unique_ptr<images::RobotProcess>> StartClockPublishers(
    const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
    const ros2_clock::SharedVirtualTime& shared);

// Lockstep: every robot with an image must have announced itself (a first
// MotorCommand) before iteration 0, so that all of them take part from the
// first step and two runs start alike. Waits on the server's socket, at most the start bound
// (timing.start_timeout_ms; unset: 10 s plus each image's boot_cost_ms, 250 ms unless its
// manifest says: 64 container images took 9.7 s to start on a loaded 2-core host,
// docs/performance.md, "Containers"). A robot whose log and CPU time stay still for
// kBootStallNs (boot_progress.h) is named before the bound: a slow fleet is waited for, a hung
// robot is not.
// `why`: what makes the run wait ("lockstep", "wait_for_robots"), the error's first word.
// An image that exits meanwhile ends the wait at once, named with its status (restart policies
// apply once the run has begun).
void WaitForRobotsToSpeak(const Scenario& scenario, std::vector<RobotSlot>& robots,
                          physics::PhysicsServer* server, const std::string& why);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ROBOT_START_H_

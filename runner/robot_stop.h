// Stopping the robots' software at the end of a run, and their peak memory.
#ifndef SITLNET_RUNNER_ROBOT_STOP_H_
#define SITLNET_RUNNER_ROBOT_STOP_H_

#include <memory>
#include <vector>

#include "robot_images/robot_images.h"
#include "runner/robot_slot.h"
#include "runner/runner.h"

namespace sitlnet::runner {

// Stops every running image (SIGTERM to all first, then a wait for each), kills what each left
// in its cgroup and reads its usage, then stops the /clock publishers. The images' peak RSS,
// read just before they are stopped, goes to report->robot_max_rss_kib and
// robot_median_rss_kib.
void StopRobots(std::vector<RobotSlot>* robots,
                std::vector<std::unique_ptr<images::RobotProcess>>* clock_publishers,
                RunReport* report);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ROBOT_STOP_H_

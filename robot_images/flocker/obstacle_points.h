// Where the flocker puts its shill agents: the obstacles it sees in one
// horizontal lidar scan, each reduced to its point nearest the robot.
// Vásárhelyi et al.'s simulation code (robotsim, Science Robotics 2018) places
// one shill agent per obstacle at its nearest point; a robot that knows
// obstacles only from its lidar treats each run of adjacent hits as one
// obstacle outline, as the DANCERS authors' flocking node does with segments
// extracted from the scan.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_OBSTACLE_POINTS_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_OBSTACLE_POINTS_H_

#include <vector>

#include "robot_images/flocker/flocking.h"

namespace sitlnet::flocker {

// One scan in the world frame: ray i leaves `origin_m` at angle
// first_ray_rad + i * ray_step_rad (counter-clockwise from world +x); a range
// >= max_range_m means the ray hit nothing. `wraps`: the last ray is adjacent
// to the first (a 360-degree scan).
struct LidarScan {
  Vec2 origin_m = Vec2::Zero();
  double first_ray_rad = 0;
  double ray_step_rad = 0;
  double max_range_m = 0;
  bool wraps = false;
  std::vector<double> ranges_m;
};

// Groups the hits into obstacles (runs of adjacent rays whose hit points are
// at most `gap_m` plus what the ray spacing explains apart, see the .cc; a
// miss or a larger jump starts a new obstacle) and
// returns, per obstacle, the point of the polyline through its hits nearest
// the origin. A lone hit is its own point. Empty when nothing was hit.
std::vector<Vec2> NearestObstaclePoints(const LidarScan& scan, double gap_m);

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_OBSTACLE_POINTS_H_

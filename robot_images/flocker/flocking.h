// VAT flocking (Vasarhelyi et al., "Optimized flocking of autonomous drones in
// confined environments", Science Robotics 2018) with the long-range
// attraction term of Bonnefond et al. (IROS 2021), in the horizontal plane.
// Pure functions of the robot's own state, what it heard from neighbours, and
// obstacle points from its lidar; the result is a desired velocity.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_

#include <Eigen/Core>
#include <vector>

namespace sitlnet::flocker {

using Vec2 = Eigen::Vector2d;

// Parameters, named as in Vasarhelyi et al. 2018 (Table S1), SI units.
struct FlockingParams {
  double flock_speed_m_s = 2.0;      // v_flock: preferred speed (towards the target).
  double max_speed_m_s = 3.0;        // v_max: cap on the commanded speed.
  double repulsion_range_m = 8.0;    // r0_rep
  double repulsion_gain = 0.6;       // p_rep (1/s)
  double attraction_range_m = 12.0;  // r0_att (Bonnefond et al.)
  double attraction_gain = 0.1;      // p_att (1/s)
  double friction_range_m = 20.0;    // r0_frict
  double friction_gain = 0.3;        // C_frict
  double friction_slack_m_s = 0.6;   // v_frict
  double friction_accel_m_s2 = 1.0;  // a_frict
  double friction_slope = 1.0;       // p_frict (1/s)
  double shill_speed_m_s = 2.5;      // v_shill
  double shill_range_m = 1.5;        // r0_shill: distance kept from obstacles
  double shill_accel_m_s2 = 2.0;     // a_shill
  double shill_slope = 2.0;          // p_shill (1/s)
};

struct Neighbour {
  Vec2 position_m;
  Vec2 velocity_m_s;
};

// The braking curve D(r, a, p) of Vasarhelyi et al. 2018 (Eq. 3): the largest
// speed from which a robot can stop within distance r with acceleration a,
// linearised with slope p at small r. Zero for r <= 0.
double BrakingSpeed(double distance_m, double accel_m_s2, double slope_1_s);

// Desired horizontal velocity of a robot at `position_m` moving at
// `velocity_m_s`, given its neighbours, obstacle surface points (e.g. lidar
// hits, world frame) and a migration target.
Vec2 DesiredVelocity(const FlockingParams& params, const Vec2& position_m, const Vec2& velocity_m_s,
                     const std::vector<Neighbour>& neighbours,
                     const std::vector<Vec2>& obstacle_points_m, const Vec2& target_m);

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_

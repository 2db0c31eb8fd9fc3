#include "robot_images/flocker/flocking.h"

#include <cmath>

namespace sitlnet::flocker {

double BrakingSpeed(double distance_m, double accel_m_s2, double slope_1_s) {
  if (distance_m <= 0) return 0;
  // Linear near zero, constant-deceleration parabola further out (Eq. 3).
  if (distance_m * slope_1_s < accel_m_s2 / slope_1_s) return distance_m * slope_1_s;
  return std::sqrt(2 * accel_m_s2 * distance_m - accel_m_s2 * accel_m_s2 / (slope_1_s * slope_1_s));
}

namespace {

// Term that damps the velocity difference `relative_m_s` when it exceeds what
// the braking curve allows at `gap_m` (shared by alignment and shill agents).
Vec2 VelocityMatching(const Vec2& relative_m_s, double allowed_m_s, double gain) {
  const double speed = relative_m_s.norm();
  if (speed <= allowed_m_s || speed == 0) return Vec2::Zero();
  return -gain * (speed - allowed_m_s) * relative_m_s / speed;
}

}  // namespace

Vec2 DesiredVelocity(const FlockingParams& p, const Vec2& position_m, const Vec2& velocity_m_s,
                     const std::vector<Neighbour>& neighbours,
                     const std::vector<Vec2>& obstacle_points_m, const Vec2& target_m) {
  Vec2 desired = Vec2::Zero();

  // Migration: self-propulsion at v_flock towards the target.
  const Vec2 to_target = target_m - position_m;
  if (to_target.norm() > 1e-6) {
    desired += p.flock_speed_m_s * to_target.normalized() *
               std::min(1.0, to_target.norm() / p.repulsion_range_m);
  }

  for (const Neighbour& n : neighbours) {
    const Vec2 offset = position_m - n.position_m;  // from neighbour to me
    const double distance = offset.norm();
    if (distance < 1e-6) continue;
    const Vec2 away = offset / distance;
    if (distance < p.repulsion_range_m) {
      desired += p.repulsion_gain * (p.repulsion_range_m - distance) * away;
    } else if (distance > p.attraction_range_m) {
      desired -= p.attraction_gain * (distance - p.attraction_range_m) * away;
    }
    const double allowed = std::max(
        p.friction_slack_m_s,
        BrakingSpeed(distance - p.friction_range_m, p.friction_accel_m_s2, p.friction_slope));
    desired += VelocityMatching(velocity_m_s - n.velocity_m_s, allowed, p.friction_gain);
  }

  // Shill agents: a virtual agent at each obstacle point moving away from it
  // at v_shill; matching its velocity steers the robot off the obstacle.
  // Only the nearest point per 45-degree sector counts, so a dense lidar scan
  // of a wall does not weigh more than a sparse one.
  constexpr int kSectors = 8;
  double nearest[kSectors];
  int nearest_index[kSectors];
  for (int s = 0; s < kSectors; ++s) {
    nearest[s] = INFINITY;
    nearest_index[s] = -1;
  }
  for (size_t i = 0; i < obstacle_points_m.size(); ++i) {
    const Vec2 offset = obstacle_points_m[i] - position_m;
    const double distance = offset.norm();
    const double angle = std::atan2(offset.y(), offset.x()) + M_PI;
    const int sector = std::min(kSectors - 1, static_cast<int>(angle / (2 * M_PI) * kSectors));
    if (distance < nearest[sector]) {
      nearest[sector] = distance;
      nearest_index[sector] = static_cast<int>(i);
    }
  }
  for (int s = 0; s < kSectors; ++s) {
    if (nearest_index[s] < 0 || nearest[s] < 1e-6) continue;
    const Vec2 offset = position_m - obstacle_points_m[nearest_index[s]];
    const Vec2 shill_velocity = p.shill_speed_m_s * offset / nearest[s];
    const double allowed =
        BrakingSpeed(nearest[s] - p.shill_range_m, p.shill_accel_m_s2, p.shill_slope);
    desired += VelocityMatching(velocity_m_s - shill_velocity, allowed, 1.0);
  }

  const double speed = desired.norm();
  if (speed > p.max_speed_m_s) desired *= p.max_speed_m_s / speed;
  return desired;
}

}  // namespace sitlnet::flocker

#include "robot_images/flocker/flocking.h"

#include <cmath>

namespace sitlnet::flocker {
namespace {

// Below this a distance or speed is treated as zero: its direction is undefined.
constexpr double kTiny = 1e-9;

// Below this speed the direction of a robot's own velocity is noise (a
// hovering quad drifts by mm/s): self-propulsion along it would fly the robot
// off in a random direction, so the term is zero until the robot moves.
constexpr double kSelfPropulsionMinSpeed_m_s = 0.1;

// The shared form of alignment and shill terms (Vásárhelyi et al.): when the
// velocity difference `other_m_s - mine_m_s` is larger than `allowed_m_s`,
// `coefficient` times the excess along that difference.
Vec2 DampExcessVelocity(const Vec2& mine_m_s, const Vec2& other_m_s, double allowed_m_s,
                        double coefficient) {
  const Vec2 difference = other_m_s - mine_m_s;
  const double speed = difference.norm();
  if (speed <= allowed_m_s || speed < kTiny) return Vec2::Zero();
  return coefficient * (speed - allowed_m_s) * difference / speed;
}

}  // namespace

double BrakingSpeed(double distance_m, double accel_m_s2, double gain_1_s) {
  if (distance_m <= 0) return 0;
  // Linear while r p < a / p, then the constant-deceleration curve; both meet
  // at r = a / p^2 with the same value a / p.
  if (distance_m * gain_1_s < accel_m_s2 / gain_1_s) return distance_m * gain_1_s;
  return std::sqrt(2 * accel_m_s2 * distance_m - accel_m_s2 * accel_m_s2 / (gain_1_s * gain_1_s));
}

Vec2 SelfPropulsionTerm(const FlockingParams& p, const Vec2& velocity_m_s) {
  const double speed = velocity_m_s.norm();
  if (speed < kSelfPropulsionMinSpeed_m_s) return Vec2::Zero();
  return p.flock_speed_m_s * velocity_m_s / speed;
}

Vec2 MigrationTerm(const FlockingParams& p, const Vec2& position_m, const Vec2& target_m) {
  const Vec2 to_target = target_m - position_m;
  const double distance = to_target.norm();
  if (distance < kTiny) return Vec2::Zero();
  return p.migration_speed_m_s * to_target / distance;
}

Vec2 RepulsionTerm(const FlockingParams& p, const Vec2& position_m,
                   const std::vector<Neighbour>& neighbours) {
  Vec2 sum = Vec2::Zero();
  for (const Neighbour& n : neighbours) {
    const Vec2 away = position_m - n.position_m;
    const double distance = away.norm();
    if (distance < kTiny || distance >= p.repulsion_range_m) continue;
    sum += p.repulsion_gain_1_s * (p.repulsion_range_m - distance) * away / distance;
  }
  return sum;
}

Vec2 AttractionTerm(const FlockingParams& p, const Vec2& position_m,
                    const std::vector<Neighbour>& neighbours) {
  Vec2 sum = Vec2::Zero();
  for (const Neighbour& n : neighbours) {
    const Vec2 towards = n.position_m - position_m;
    const double distance = towards.norm();
    if (distance <= p.attraction_range_m) continue;
    sum += p.attraction_gain_1_s * (distance - p.attraction_range_m) * towards / distance;
  }
  return sum;
}

Vec2 AlignmentTerm(const FlockingParams& p, const Vec2& position_m, const Vec2& velocity_m_s,
                   const std::vector<Neighbour>& neighbours) {
  Vec2 sum = Vec2::Zero();
  for (const Neighbour& n : neighbours) {
    const double distance = (position_m - n.position_m).norm();
    const double allowed = std::max(
        p.friction_slack_m_s,
        BrakingSpeed(distance - p.friction_range_m, p.friction_accel_m_s2, p.friction_gain_1_s));
    sum += DampExcessVelocity(velocity_m_s, n.velocity_m_s, allowed, p.friction_coefficient);
  }
  return sum;
}

Vec2 ShillTerm(const FlockingParams& p, const Vec2& position_m, const Vec2& velocity_m_s,
               const std::vector<Vec2>& shill_points_m) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& point : shill_points_m) {
    const Vec2 away = position_m - point;
    const double distance = away.norm();
    if (distance < kTiny) continue;  // On the surface: no outward direction.
    const Vec2 shill_velocity = p.shill_speed_m_s * away / distance;
    const double allowed =
        BrakingSpeed(distance - p.shill_range_m, p.shill_accel_m_s2, p.shill_gain_1_s);
    sum += DampExcessVelocity(velocity_m_s, shill_velocity, allowed, 1.0);
  }
  return sum;
}

Vec2 DesiredVelocity(const FlockingParams& p, const Vec2& position_m, const Vec2& velocity_m_s,
                     const std::vector<Neighbour>& neighbours,
                     const std::vector<Vec2>& shill_points_m, const Vec2& target_m) {
  Vec2 desired = SelfPropulsionTerm(p, velocity_m_s) + MigrationTerm(p, position_m, target_m) +
                 RepulsionTerm(p, position_m, neighbours) +
                 AttractionTerm(p, position_m, neighbours) +
                 AlignmentTerm(p, position_m, velocity_m_s, neighbours) +
                 ShillTerm(p, position_m, velocity_m_s, shill_points_m);
  const double speed = desired.norm();
  if (speed > p.max_speed_m_s) desired *= p.max_speed_m_s / speed;
  return desired;
}

}  // namespace sitlnet::flocker

#include "robot_images/flocker/obstacle_points.h"

#include <algorithm>
#include <cmath>

namespace sitlnet::flocker {
namespace {

// The point of segment [a, b] nearest `p`.
Vec2 NearestOnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 == 0) return a;
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return a + t * ab;
}

// Whether ray i hit something, and where.
bool Hit(const LidarScan& scan, size_t i, Vec2* point_m) {
  const double range = scan.ranges_m[i];
  if (!(range < scan.max_range_m)) return false;
  const double angle = scan.first_ray_rad + double(i) * scan.ray_step_rad;
  *point_m = scan.origin_m + range * Vec2(std::cos(angle), std::sin(angle));
  return true;
}

// Adjacent hits on one flat surface are further apart the further away and
// the more obliquely it is seen: up to r sin(step) / sin(lambda - step) for a
// surface seen at lambda or more from the ray (the adaptive breakpoint of
// Borges and Aldon, "Line extraction in 2D range images for mobile robotics",
// J. Intelligent and Robotic Systems, 2004). Surfaces seen more obliquely
// than this may split into several obstacles, whose extra nearest points are
// then at least twice as far as the surface's foot.
constexpr double kMinIncidence_rad = 30 * M_PI / 180;

double MaxJump(const LidarScan& scan, double range_m, double gap_m) {
  const double step = std::fabs(scan.ray_step_rad);
  if (step >= kMinIncidence_rad) return gap_m;
  return gap_m + range_m * std::sin(step) / std::sin(kMinIncidence_rad - step);
}

// Whether rays `before` and `here` belong to different obstacles (or no obstacle).
bool Break(const LidarScan& scan, size_t before, size_t here, double gap_m) {
  Vec2 a, b;
  return !Hit(scan, before, &a) || !Hit(scan, here, &b) ||
         (b - a).norm() > MaxJump(scan, scan.ranges_m[before], gap_m);
}

}  // namespace

std::vector<Vec2> NearestObstaclePoints(const LidarScan& scan, double gap_m) {
  const size_t rays = scan.ranges_m.size();
  // A run must not be split where the scan wraps: start after a break.
  // Hits all around, all close: one obstacle, any start will do.
  size_t start = 0;
  if (scan.wraps) {
    for (size_t i = 0; i < rays; ++i) {
      if (Break(scan, (i + rays - 1) % rays, i, gap_m)) {
        start = i;
        break;
      }
    }
  }
  std::vector<Vec2> points;
  bool in_run = false;  // The previous ray hit and belongs to the current run.
  Vec2 previous = Vec2::Zero(), nearest = Vec2::Zero();
  double nearest_distance = INFINITY;
  for (size_t k = 0; k < rays; ++k) {
    const size_t i = (start + k) % rays;
    Vec2 hit;
    const bool hit_here = Hit(scan, i, &hit);
    if (in_run && Break(scan, (i + rays - 1) % rays, i, gap_m)) {
      points.push_back(nearest);
      in_run = false;
    }
    if (!hit_here) continue;
    // Within a run, the outline between two hits is the segment joining them.
    const Vec2 candidate = in_run ? NearestOnSegment(scan.origin_m, previous, hit) : hit;
    const double distance = (candidate - scan.origin_m).norm();
    if (!in_run || distance < nearest_distance) {
      nearest_distance = distance;
      nearest = candidate;
    }
    in_run = true;
    previous = hit;
  }
  if (in_run) points.push_back(nearest);
  return points;
}

}  // namespace sitlnet::flocker

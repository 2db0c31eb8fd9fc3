#include "robot_images/flocker/obstacle_points.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sitlnet::flocker {
namespace {

struct Segment {
  Vec2 a, b;
};

// An independent ray caster: the first crossing of each ray with the walls.
LidarScan Scan(const Vec2& origin, const std::vector<Segment>& walls, int rays, double first_rad,
               double max_range_m) {
  LidarScan scan;
  scan.origin_m = origin;
  scan.first_ray_rad = first_rad;
  scan.ray_step_rad = 2 * M_PI / rays;
  scan.max_range_m = max_range_m;
  scan.wraps = true;
  for (int i = 0; i < rays; ++i) {
    const double angle = first_rad + i * scan.ray_step_rad;
    const Vec2 d(std::cos(angle), std::sin(angle));
    double best = max_range_m;
    for (const Segment& w : walls) {
      // origin + t d = a + s (b - a), solved by Cramer's rule.
      const Vec2 e = w.b - w.a, f = w.a - origin;
      const double det = d.x() * -e.y() + e.x() * d.y();
      if (std::fabs(det) < 1e-12) continue;
      const double t = (f.x() * -e.y() + e.x() * f.y()) / det;
      const double s = (d.x() * f.y() - d.y() * f.x()) / det;
      if (t > 0 && s >= 0 && s <= 1) best = std::min(best, t);
    }
    scan.ranges_m.push_back(best);
  }
  return scan;
}

TEST(NearestObstaclePointsTest, NothingHitNoPoints) {
  EXPECT_TRUE(NearestObstaclePoints(Scan({0, 0}, {}, 36, -M_PI, 15), 3).empty());
}

TEST(NearestObstaclePointsTest, AWallIsOnePointAtItsFootEvenBetweenRays) {
  // Rays at +-5 degrees straddle the wall's normal: the nearest point lies on
  // the segment between their hits, (5, 0), not on either hit (5, +-0.437).
  const auto points =
      NearestObstaclePoints(Scan({0, 0}, {{{5, -20}, {5, 20}}}, 36, -M_PI + 5 * M_PI / 180, 15), 3);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].x(), 5, 1e-9);
  EXPECT_NEAR(points[0].y(), 0, 1e-9);
}

TEST(NearestObstaclePointsTest, SeparateObstaclesEachGetTheirNearestPoint) {
  // A wall ahead and a shorter one to the left, with missed rays between.
  const auto points =
      NearestObstaclePoints(Scan({0, 0}, {{{5, -3}, {5, 3}}, {{-3, 6}, {3, 6}}}, 72, -M_PI, 15), 3);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[0].x(), 5, 1e-9);  // Counter-clockwise from -180 deg: the wall ahead first.
  EXPECT_NEAR(points[0].y(), 0, 1e-9);
  EXPECT_NEAR(points[1].x(), 0, 1e-9);
  EXPECT_NEAR(points[1].y(), 6, 1e-9);
}

TEST(NearestObstaclePointsTest, ARangeJumpSplitsObstacles) {
  // Two walls overlapping in angle, 8 m apart in depth. From the last hit on
  // the near wall, (4, -0.705) at -10 deg, to the first on the far one,
  // (12, -3.215) at -15 deg, is 8.38 m: more than 3 m plus the 0.84 m that
  // 4.06 m * sin(5 deg) / sin(25 deg) allows, so each keeps its own point;
  // with a 10 m gap they are one obstacle whose nearest point is the near wall's.
  const std::vector<Segment> walls = {{{4, -1}, {4, 4}}, {{12, -6}, {12, -1.5}}};
  const LidarScan scan = Scan({0, 0}, walls, 72, -M_PI, 15);
  EXPECT_EQ(NearestObstaclePoints(scan, 3).size(), 2u);
  const auto merged = NearestObstaclePoints(scan, 10);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_NEAR(merged[0].x(), 4, 1e-9);
  EXPECT_NEAR(merged[0].y(), 0, 1e-9);
}

TEST(NearestObstaclePointsTest, AnObstacleAcrossTheScanSeamIsOne) {
  // Behind the robot the wall spans the first and the last rays.
  const auto points =
      NearestObstaclePoints(Scan({0, 0}, {{{-5, -20}, {-5, 20}}}, 36, -M_PI, 15), 3);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].x(), -5, 1e-9);
  EXPECT_NEAR(points[0].y(), 0, 1e-9);
}

TEST(NearestObstaclePointsTest, WorldFrameOrigin) {
  const auto points =
      NearestObstaclePoints(Scan({100, 50}, {{{97, 40}, {97, 60}}}, 36, -M_PI, 15), 3);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].x(), 97, 1e-9);
  EXPECT_NEAR(points[0].y(), 50, 1e-9);
}

}  // namespace
}  // namespace sitlnet::flocker

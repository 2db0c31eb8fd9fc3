#include "robot_images/flocker/flocking.h"

#include <gtest/gtest.h>

namespace sitlnet::flocker {
namespace {

TEST(BrakingSpeedTest, MatchesClosedFormOnBothBranches) {
  EXPECT_EQ(BrakingSpeed(-1, 1, 1), 0);
  // Linear branch: r*p < a/p.
  EXPECT_DOUBLE_EQ(BrakingSpeed(0.5, 1, 1), 0.5);
  // Parabolic branch: v = sqrt(2 a r - a^2/p^2); continuous at r = a/p^2.
  EXPECT_DOUBLE_EQ(BrakingSpeed(4, 2, 1), std::sqrt(16.0 - 4.0));
  EXPECT_NEAR(BrakingSpeed(1 - 1e-12, 1, 1), BrakingSpeed(1 + 1e-12, 1, 1), 1e-6);
}

TEST(FlockingTest, AloneItMigratesAtFlockSpeed) {
  FlockingParams params;
  const Vec2 v = DesiredVelocity(params, {0, 0}, {0, 0}, {}, {}, {100, 0});
  EXPECT_NEAR(v.x(), params.flock_speed_m_s, 1e-9);
  EXPECT_NEAR(v.y(), 0, 1e-9);
}

TEST(FlockingTest, CloseNeighbourRepelsFarNeighbourAttracts) {
  FlockingParams params;
  params.flock_speed_m_s = 0;
  params.friction_gain = 0;
  const Vec2 close = DesiredVelocity(params, {0, 0}, {0, 0}, {{{2, 0}, {0, 0}}}, {}, {0, 0});
  EXPECT_LT(close.x(), 0);
  const Vec2 far = DesiredVelocity(params, {0, 0}, {0, 0}, {{{30, 0}, {0, 0}}}, {}, {0, 0});
  EXPECT_GT(far.x(), 0);
  const Vec2 between = DesiredVelocity(params, {0, 0}, {0, 0}, {{{10, 0}, {0, 0}}}, {}, {0, 0});
  EXPECT_NEAR(between.norm(), 0, 1e-12);
}

TEST(FlockingTest, AlignmentDampsVelocityDifference) {
  FlockingParams params;
  params.flock_speed_m_s = 0;
  const Vec2 v = DesiredVelocity(params, {0, 0}, {0, 0}, {{{10, 0}, {0, 2}}}, {}, {0, 0});
  EXPECT_GT(v.y(), 0);  // speeds up towards the neighbour's velocity
}

TEST(FlockingTest, ObstacleAheadPushesBack) {
  FlockingParams params;
  params.flock_speed_m_s = 0;
  const Vec2 v = DesiredVelocity(params, {0, 0}, {1, 0}, {}, {{1.0, 0}}, {0, 0});
  EXPECT_LT(v.x(), 0);
}

TEST(FlockingTest, SpeedIsCapped) {
  FlockingParams params;
  const Vec2 v = DesiredVelocity(params, {0, 0}, {0, 0}, {{{0.1, 0}, {0, 0}}}, {}, {100, 0});
  EXPECT_LE(v.norm(), params.max_speed_m_s + 1e-12);
}

}  // namespace
}  // namespace sitlnet::flocker

#include "robot_images/flocker/neighbour_table.h"

namespace sitlnet::flocker {
namespace {

TEST(NeighbourTableTest, ForgetsAfterTimeoutWithoutNews) {
  NeighbourTable table(2'000'000'000);
  table.Heard(1, {{1, 0}, {0, 0}}, 0);
  table.Heard(2, {{2, 0}, {0, 0}}, 1'500'000'000);
  EXPECT_EQ(table.Current(2'000'000'000).size(), 2u);
  EXPECT_EQ(table.Current(2'000'000'001).size(), 1u);  // robot 1 silent for > 2 s
  EXPECT_EQ(table.Indices(), std::vector<uint32_t>{2});
  table.Heard(1, {{1, 0}, {0, 0}}, 2'500'000'000);  // news again: back
  EXPECT_EQ(table.Current(3'000'000'000).size(), 2u);
}

}  // namespace
}  // namespace sitlnet::flocker

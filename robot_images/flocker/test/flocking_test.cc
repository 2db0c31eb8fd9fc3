// Each VAT term against values worked out by hand from the formulas in
// docs/case-study.md (checked against implementations, not the papers' text); the arithmetic is in
// the comments.
#include "robot_images/flocker/flocking.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sitlnet::flocker {
namespace {

constexpr double kTolerance = 1e-9;

// The case study's parameters, spelled out so the hand computations below do
// not depend on the library's defaults.
FlockingParams CaseStudyParams() {
  FlockingParams p;
  p.flock_speed_m_s = 1.5;
  p.max_speed_m_s = 1.0;
  p.migration_speed_m_s = 0.7;
  p.repulsion_range_m = 5;
  p.repulsion_gain_1_s = 0.13;
  p.attraction_range_m = 5;
  p.attraction_gain_1_s = 0.08;
  p.friction_range_m = 85.3;
  p.friction_coefficient = 0.8;
  p.friction_slack_m_s = 0.63;
  p.friction_accel_m_s2 = 4.16;
  p.friction_gain_1_s = 3.2;
  p.shill_range_m = 0.3;
  p.shill_speed_m_s = 13.6;
  p.shill_accel_m_s2 = 53;
  p.shill_gain_1_s = 3.55;
  return p;
}

void ExpectVec(const Vec2& actual, double x, double y, double tolerance = kTolerance) {
  EXPECT_NEAR(actual.x(), x, tolerance);
  EXPECT_NEAR(actual.y(), y, tolerance);
}

TEST(BrakingSpeedTest, BothBranchesAndTheJoint) {
  // a = 4.16, p = 3.2: the linear branch holds while r p < a / p = 1.3.
  EXPECT_EQ(BrakingSpeed(0, 4.16, 3.2), 0);
  EXPECT_EQ(BrakingSpeed(-2, 4.16, 3.2), 0);
  EXPECT_NEAR(BrakingSpeed(0.25, 4.16, 3.2), 0.8, kTolerance);  // 0.25 * 3.2
  // sqrt(2 * 4.16 * 10 - 4.16^2 / 3.2^2) = sqrt(83.2 - 1.69) = sqrt(81.51).
  EXPECT_NEAR(BrakingSpeed(10, 4.16, 3.2), 9.028288874, 1e-9);
  // Both branches give a / p = 1.3 at r = a / p^2 = 0.40625.
  EXPECT_NEAR(BrakingSpeed(0.40625 - 1e-12, 4.16, 3.2), 1.3, 1e-9);
  EXPECT_NEAR(BrakingSpeed(0.40625 + 1e-12, 4.16, 3.2), 1.3, 1e-9);
}

TEST(FlockingTermsTest, SelfPropulsionFollowsTheRobotsOwnVelocity) {
  const FlockingParams p = CaseStudyParams();
  ExpectVec(SelfPropulsionTerm(p, {3, 4}), 0.9, 1.2);  // 1.5 * (0.6, 0.8)
  // A hovering robot's drift has no meaningful direction.
  ExpectVec(SelfPropulsionTerm(p, {0.05, 0}), 0, 0);
}

TEST(FlockingTermsTest, MigrationPointsAtTheTarget) {
  const FlockingParams p = CaseStudyParams();
  ExpectVec(MigrationTerm(p, {1, 1}, {4, 5}), 0.42, 0.56);  // 0.7 * (0.6, 0.8)
  ExpectVec(MigrationTerm(p, {4, 5}, {4, 5}), 0, 0);
}

TEST(FlockingTermsTest, RepulsionIsAHalfSpringBelowItsRange) {
  const FlockingParams p = CaseStudyParams();
  // Neighbour 2 m away along (0.6, 0.8): 0.13 * (5 - 2) = 0.39 away from it.
  ExpectVec(RepulsionTerm(p, {0, 0}, {{{1.2, 1.6}, {0, 0}}}), -0.234, -0.312);
  ExpectVec(RepulsionTerm(p, {0, 0}, {{{5, 0}, {0, 0}}}), 0, 0);  // at r0_rep
  ExpectVec(RepulsionTerm(p, {0, 0}, {{{6, 0}, {0, 0}}}), 0, 0);
}

TEST(FlockingTermsTest, AttractionIsAHalfSpringAboveItsRange) {
  const FlockingParams p = CaseStudyParams();
  // Neighbour 10 m away along (0.6, 0.8): 0.08 * (10 - 5) = 0.4 towards it.
  ExpectVec(AttractionTerm(p, {0, 0}, {{{6, 8}, {0, 0}}}), 0.24, 0.32);
  ExpectVec(AttractionTerm(p, {0, 0}, {{{2, 0}, {0, 0}}}), 0, 0);
  // Terms add over neighbours: 0.08 * 5 along +x and 0.08 * 15 along -y.
  ExpectVec(AttractionTerm(p, {0, 0}, {{{10, 0}, {0, 0}}, {{0, -20}, {0, 0}}}), 0.4, -1.2);
}

TEST(FlockingTermsTest, AlignmentDampsOnlyTheExcessOverTheBrakingCurve) {
  const FlockingParams p = CaseStudyParams();
  // 10 m apart: D(10 - 85.3) = 0, so v_frictmax = v_frict = 0.63 and the
  // 2 m/s difference gives 0.8 * (2 - 0.63) = 1.096 towards the neighbour's velocity.
  ExpectVec(AlignmentTerm(p, {0, 0}, {0, 0}, {{{10, 0}, {0, 2}}}), 0, 1.096);
  // 85.8 m apart: D(0.5, 4.16, 3.2) = sqrt(4.16 - 1.69) = 1.571623..., so
  // 0.8 * (2 - 1.571623) = 0.342701...
  ExpectVec(AlignmentTerm(p, {0, 0}, {0, 0}, {{{85.8, 0}, {0, 2}}}), 0, 0.3427013, 1e-6);
  // 100 m apart: D(14.7) = sqrt(122.304 - 1.69) = 10.98 > 2: no alignment.
  ExpectVec(AlignmentTerm(p, {0, 0}, {0, 0}, {{{100, 0}, {0, 2}}}), 0, 0);
  // A difference within the slack v_frict is left alone.
  ExpectVec(AlignmentTerm(p, {0, 0}, {0, 0}, {{{10, 0}, {0.5, 0}}}), 0, 0);
}

TEST(FlockingTermsTest, ShillAgentPushesOffAnObstacleWithinItsBrakingDistance) {
  const FlockingParams p = CaseStudyParams();
  // Robot at the origin flying +x at 1 m/s, wall point 2 m ahead: the shill
  // agent moves at 13.6 m/s towards -x, a difference of 14.6 m/s; allowed
  // D(2 - 0.3, 53, 3.55) = 1.7 * 3.55 = 6.035 (linear: 6.035 < 53 / 3.55).
  ExpectVec(ShillTerm(p, {0, 0}, {1, 0}, {{2, 0}}), -(14.6 - 6.035), 0);
  // 5 m away: D(4.7) = sqrt(498.2 - 53^2 / 3.55^2) = 16.59 > 14.6: nothing.
  ExpectVec(ShillTerm(p, {0, 0}, {1, 0}, {{5, 0}}), 0, 0);
}

TEST(DesiredVelocityTest, SumsTheTermsAndCapsAtMaxSpeed) {
  FlockingParams p = CaseStudyParams();
  const Vec2 position(0, 0), velocity(0.6, 0.8), target(1000, 0);
  const std::vector<Neighbour> neighbours = {{{3, 0}, {0, 0}}, {{0, 12}, {1, 1}}};
  const std::vector<Vec2> shill = {{0, -2}};
  const Vec2 sum =
      SelfPropulsionTerm(p, velocity) + MigrationTerm(p, position, target) +
      RepulsionTerm(p, position, neighbours) + AttractionTerm(p, position, neighbours) +
      AlignmentTerm(p, position, velocity, neighbours) + ShillTerm(p, position, velocity, shill);
  ASSERT_GT(sum.norm(), p.max_speed_m_s);
  const Vec2 capped = DesiredVelocity(p, position, velocity, neighbours, shill, target);
  EXPECT_NEAR(capped.norm(), p.max_speed_m_s, kTolerance);
  ExpectVec(capped, sum.x() / sum.norm(), sum.y() / sum.norm());
  p.max_speed_m_s = 100;  // Below the cap the sum is returned as is.
  const Vec2 uncapped = DesiredVelocity(p, position, velocity, neighbours, shill, target);
  ExpectVec(uncapped, sum.x(), sum.y());
}

TEST(DesiredVelocityTest, AloneAtRestItMigrates) {
  const FlockingParams p = CaseStudyParams();
  ExpectVec(DesiredVelocity(p, {0, 0}, {0, 0}, {}, {}, {10000, 0}), 0.7, 0);
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

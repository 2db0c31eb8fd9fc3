// ComparePathsFromLiftOff on paths built by hand: the same climb started at different times is
// no gap once aligned; an offset of known size is that size.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

// trajectories.csv rows at 10 Hz for 20 s: robot 0 on the ground at z 0.1 until `lift_off_s`,
// then climbing 1 m/s, shifted by `dx_m`; robot 1 still at the origin.
std::string Trajectories(double lift_off_s, double dx_m) {
  std::string csv = "time_s,robot,x_m,y_m,z_m\n";
  char row[128];
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 10.0;
    const double z = t < lift_off_s ? 0.1 : 0.1 + (t - lift_off_s);
    std::snprintf(row, sizeof row, "%.3f,0,%.3f,2.000,%.3f\n%.3f,1,0.000,0.000,0.100\n", t,
                  1.0 + dx_m, z, t);
    csv += row;
  }
  return csv;
}

TEST(PathGapTest, AlignsAtLiftOff) {
  const std::optional<PathGap> gap =
      ComparePathsFromLiftOff(Trajectories(9.0, 0), Trajectories(9.7, 0), 0);
  ASSERT_TRUE(gap);
  EXPECT_NEAR(gap->worst_m, 0, 1e-9);
  ASSERT_TRUE(gap->lift_off_s[0] && gap->lift_off_s[1]);
  // The first row 5 cm above 0.1 m: 0.1 s after the climb starts.
  EXPECT_NEAR(*gap->lift_off_s[0], 9.1, 1e-9);
  EXPECT_NEAR(*gap->lift_off_s[1], 9.8, 1e-9);
  EXPECT_NEAR(gap->compared_s, 20 - 9.8, 1e-9);
}

TEST(PathGapTest, MeasuresAnOffset) {
  const std::optional<PathGap> gap =
      ComparePathsFromLiftOff(Trajectories(9.0, 0), Trajectories(9.0, 0.25), 0);
  ASSERT_TRUE(gap);
  EXPECT_NEAR(gap->worst_m, 0.25, 1e-9);
  EXPECT_NEAR(gap->worst_horizontal_m, 0.25, 1e-9);
  EXPECT_NEAR(gap->worst_vertical_m, 0, 1e-9);
}

TEST(PathGapTest, ARobotOnTheGroundIsComparedFromTheStart) {
  const std::optional<PathGap> gap =
      ComparePathsFromLiftOff(Trajectories(9.0, 0), Trajectories(9.5, 0), 1);
  ASSERT_TRUE(gap);
  EXPECT_FALSE(gap->lift_off_s[0]);
  EXPECT_NEAR(gap->worst_m, 0, 1e-9);
  EXPECT_NEAR(gap->compared_s, 20, 1e-9);
}

TEST(PathGapTest, LiftOffInOneRunOnlyOrNoRowsIsNoAnswer) {
  EXPECT_FALSE(ComparePathsFromLiftOff(Trajectories(9.0, 0), Trajectories(30, 0), 0));
  EXPECT_FALSE(ComparePathsFromLiftOff(Trajectories(9.0, 0), Trajectories(9.0, 0), 2));
}

}  // namespace
}  // namespace sitlnet::verify

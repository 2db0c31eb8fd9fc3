// summary.json's "separation": the closest two robots came over the samples, by brute force on
// hand-placed positions (the oracle is the arithmetic: a 3-4-5 triangle, a tie, a later miss).
#include "run_formats/run_formats.h"

#include <gtest/gtest.h>

namespace sitlnet::run_formats {
namespace {

TEST(ClosestApproachTest, NullUntilTwoRobotsAreSampled) {
  ClosestApproachTracker tracker;
  EXPECT_FALSE(tracker.closest());
  tracker.Sample(0, {1, 2, 3});
  EXPECT_FALSE(tracker.closest());
}

TEST(ClosestApproachTest, KeepsTheSmallestDistanceItsFirstInstantAndThePair) {
  ClosestApproachTracker tracker;
  // t = 0: a at the origin, b 12 m away, c 13 m from b in 3D (3, 4, 12).
  tracker.Sample(0, {0, 0, 0, 12, 0, 0, 15, 4, 12});
  ASSERT_TRUE(tracker.closest());
  EXPECT_DOUBLE_EQ(tracker.closest()->distance_m, 12);
  // t = 1 s: c comes to 5 m of b (3, 4, 0): the new closest.
  tracker.Sample(kNsPerS, {0, 0, 0, 12, 0, 0, 15, 4, 0});
  EXPECT_DOUBLE_EQ(tracker.closest()->distance_m, 5);
  EXPECT_EQ(tracker.closest()->time_ns, kNsPerS);
  EXPECT_EQ(tracker.closest()->robot_a, 1);
  EXPECT_EQ(tracker.closest()->robot_b, 2);
  // t = 2 s: the same 5 m again, between a and c: the first instant and pair stay.
  tracker.Sample(2 * kNsPerS, {0, 0, 0, 40, 0, 0, 3, 4, 0});
  EXPECT_EQ(tracker.closest()->time_ns, kNsPerS);
  EXPECT_EQ(tracker.closest()->robot_a, 1);
  // t = 3 s: everyone farther: nothing changes.
  tracker.Sample(3 * kNsPerS, {0, 0, 0, 100, 0, 0, 0, 100, 0});
  EXPECT_DOUBLE_EQ(tracker.closest()->distance_m, 5);
}

}  // namespace
}  // namespace sitlnet::run_formats

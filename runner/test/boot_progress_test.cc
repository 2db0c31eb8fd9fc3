#include "runner/boot_progress.h"

#include <gtest/gtest.h>

namespace sitlnet::runner {
namespace {

constexpr TimeNs kS = kNsPerS;

TEST(BootProgressTest, AGrowingLogIsProgressAndAStillOneIsNot) {
  BootProgress progress(2, 2, 0);
  progress.Observe(0, {100, -1}, 2, 1 * kS);
  progress.Observe(1, {100, -1}, 2, 1 * kS);
  for (TimeNs t = 2; t <= 12; ++t) {
    progress.Observe(0, {100 + t, -1}, 2, t * kS);  // Logs a byte a second.
    progress.Observe(1, {100, -1}, 2, t * kS);      // Logs nothing, no CPU accounted.
  }
  EXPECT_EQ(progress.StillForNs(0, 12 * kS), 0);
  EXPECT_EQ(progress.StillForNs(1, 12 * kS), 12 * kS) << "still since the start";
}

// Half of the fair share counts: on 2 cores, 16 booting robots get 1/8 of a core each.
TEST(BootProgressTest, CpuCountsFromHalfTheFairShareOfTheCores) {
  BootProgress progress(3, 2, 0);
  for (int robot = 0; robot < 3; ++robot) progress.Observe(robot, {0, 0}, 16, 0);
  const TimeNs wall = 4 * kS;
  progress.Observe(0, {0, wall / 8}, 16, wall);        // Its fair share: progress.
  progress.Observe(1, {0, wall / 16 + 1}, 16, wall);   // Just above half of it: progress.
  progress.Observe(2, {0, wall / 16 - kNsPerMs}, 16, wall);  // Just below: still.
  EXPECT_EQ(progress.StillForNs(0, wall), 0);
  EXPECT_EQ(progress.StillForNs(1, wall), 0);
  EXPECT_EQ(progress.StillForNs(2, wall), wall);
}

// A lone robot's fair share is one core: PX4 waiting for a simulator that never answers
// (15 % of a core, measured) is not booting.
TEST(BootProgressTest, ALoneRobotWaitingAtFifteenPercentOfACoreIsStill) {
  BootProgress progress(1, 2, 0);
  progress.Observe(0, {500, 0}, 1, 0);
  for (TimeNs t = 1; t <= 10; ++t) progress.Observe(0, {500, t * kS * 15 / 100}, 1, t * kS);
  EXPECT_EQ(progress.StillForNs(0, 10 * kS), 10 * kS);
}

TEST(BootProgressTest, TheFirstSampleIsTheBaseline) {
  BootProgress progress(1, 1, 0);
  progress.Observe(0, {1 << 20, 50 * kS}, 1, 3 * kS);  // What it did before is not progress.
  EXPECT_EQ(progress.StillForNs(0, 3 * kS), 3 * kS);
}

}  // namespace
}  // namespace sitlnet::runner

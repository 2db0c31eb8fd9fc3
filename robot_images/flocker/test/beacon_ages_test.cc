// The flocker's beacon-age summary: median and maximum of one log period, then empty again.
#include "robot_images/flocker/beacon_ages.h"

#include <gtest/gtest.h>

namespace sitlnet::flocker {
namespace {

TEST(BeaconAgesTest, SummarisesOnePeriodInWholeMillisecondsThenForgets) {
  BeaconAges ages;
  EXPECT_EQ(ages.TakeSummaryMs(), "-");
  ages.Add(1'000'000'000, 1'010'000'000);  // 10 ms
  ages.Add(2'000'000'000, 2'250'700'000);  // 250.7 ms
  ages.Add(3'000'000'000, 3'020'000'000);  // 20 ms
  EXPECT_EQ(ages.TakeSummaryMs(), "20/250");
  EXPECT_EQ(ages.TakeSummaryMs(), "-");
  ages.Add(0, 30'000'000);
  ages.Add(0, 10'000'000);
  EXPECT_EQ(ages.TakeSummaryMs(), "10/30") << "even count: the lower middle value";
}

}  // namespace
}  // namespace sitlnet::flocker

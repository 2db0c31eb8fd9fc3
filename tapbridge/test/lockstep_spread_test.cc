#include "tapbridge/lockstep_spread.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/common.h"

namespace sitlnet::tapbridge {
namespace {

// The first `count` offsets a robot's frames get within a 10 ms step.
std::vector<TimeNs> Offsets(uint64_t seed, uint64_t robot, int count = 16) {
  std::mt19937_64 stream = LockstepSpreadStream(seed, robot);
  std::uniform_int_distribution<TimeNs> offset(0, 10 * kNsPerMs - 1);
  std::vector<TimeNs> result;
  for (int k = 0; k < count; ++k) result.push_back(offset(stream));
  return result;
}

TEST(LockstepSpread, SeedsThatDifferOnlyInTheHigh32BitsGiveDifferentSpreads) {
  // std::seed_seq truncates each value to 32 bits: fed the 64-bit seed whole, these two seeds
  // gave every robot the same stream.
  EXPECT_NE(Offsets(0x0000'0001'0000'0005, 0), Offsets(0x0000'0002'0000'0005, 0));
  EXPECT_NE(Offsets(0xffff'ffff'0000'0000, 3), Offsets(0x0000'0000'0000'0000, 3));
}

TEST(LockstepSpread, SameSeedSameStreamAndRobotsDiffer) {
  EXPECT_EQ(Offsets(42, 1), Offsets(42, 1));
  EXPECT_NE(Offsets(42, 1), Offsets(42, 2));
  EXPECT_NE(Offsets(42, 1), Offsets(43, 1));
}

}  // namespace
}  // namespace sitlnet::tapbridge

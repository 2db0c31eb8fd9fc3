// --pacing's spelling and the pacing type round-trip (clock/pacing.h).
#include "clock/pacing.h"

#include <gtest/gtest.h>

namespace sitlnet::clock {
namespace {

TEST(PacingTest, NamesParseBack) {
  for (Pacing pacing : {Pacing::kRealtime, Pacing::kLockstep}) {
    EXPECT_EQ(ParsePacing(PacingName(pacing)), pacing);
  }
  EXPECT_EQ(PacingName(Pacing::kLockstep), "lockstep");
  EXPECT_FALSE(ParsePacing("PACING_LOCKSTEP").has_value());
}

}  // namespace
}  // namespace sitlnet::clock

#include "coordinator/pacer.h"

#include <gtest/gtest.h>

namespace sitlnet::coordinator {
namespace {

constexpr TimeNs kOrigin = 5 * kNsPerS;

TEST(Pacer, RealtimeDeadlineIsOriginPlusVirtualEnd) {
  Pacer pacer(Pacing::kRealtime, 1.0, 10 * kNsPerMs);
  pacer.Begin(kOrigin);
  EXPECT_EQ(pacer.DeadlineNs(0), kOrigin + 10 * kNsPerMs);
  EXPECT_EQ(pacer.DeadlineNs(99), kOrigin + kNsPerS);
}

TEST(Pacer, RealtimeFactorScalesWallTime) {
  // Factor 2: virtual time runs twice as fast as the wall clock.
  Pacer fast(Pacing::kRealtime, 2.0, 10 * kNsPerMs);
  fast.Begin(kOrigin);
  EXPECT_EQ(fast.DeadlineNs(0), kOrigin + 5 * kNsPerMs);
  // Factor 0.5: half speed. No accumulated rounding after a million iterations.
  Pacer slow(Pacing::kRealtime, 0.5, 10 * kNsPerMs);
  slow.Begin(kOrigin);
  EXPECT_EQ(slow.DeadlineNs(999'999), kOrigin + 20'000 * kNsPerS);
  // A factor that does not divide evenly: 1/3 of 10 ms is 3.3333... ms, rounded up to the
  // next wall nanosecond (clock/clock.h's rule: no iteration ends before its virtual time).
  Pacer third(Pacing::kRealtime, 3.0, 10 * kNsPerMs);
  third.Begin(0);
  EXPECT_EQ(third.DeadlineNs(0), 3'333'334);
  EXPECT_EQ(third.DeadlineNs(2), 10 * kNsPerMs);
}

TEST(Pacer, EarlyIterationSleepsToItsDeadlineWithoutLag) {
  Pacer pacer(Pacing::kRealtime, 1.0, 10 * kNsPerMs);
  pacer.Begin(kOrigin);
  const Pacer::Decision d = pacer.AfterIteration(0, kOrigin + 3 * kNsPerMs);
  EXPECT_EQ(d.sleep_until_ns, kOrigin + 10 * kNsPerMs);
  EXPECT_EQ(d.lag_ns, 0);
}

TEST(Pacer, LateIterationReportsLagAndDoesNotShiftLaterDeadlines) {
  Pacer pacer(Pacing::kRealtime, 1.0, 10 * kNsPerMs);
  pacer.Begin(kOrigin);
  const Pacer::Decision late = pacer.AfterIteration(0, kOrigin + 25 * kNsPerMs);
  EXPECT_EQ(late.lag_ns, 15 * kNsPerMs);
  EXPECT_LE(late.sleep_until_ns, kOrigin + 25 * kNsPerMs);  // No sleep.
  // Iteration 1 still ends at origin + 20 ms: 5 ms late; iteration 2 on time.
  EXPECT_EQ(pacer.AfterIteration(1, kOrigin + 25 * kNsPerMs + 1).lag_ns, 5 * kNsPerMs + 1);
  EXPECT_EQ(pacer.AfterIteration(2, kOrigin + 26 * kNsPerMs).lag_ns, 0);
}

TEST(Pacer, LockstepNeverSleepsAndHasNoLag) {
  Pacer pacer(Pacing::kLockstep, 1.0, 10 * kNsPerMs);
  pacer.Begin(kOrigin);
  const Pacer::Decision d = pacer.AfterIteration(50, kOrigin + kNsPerMs);
  EXPECT_LE(d.sleep_until_ns, kOrigin + kNsPerMs);
  EXPECT_EQ(d.lag_ns, 0);
}

TEST(Pacer, RejectsNonPositiveFactor) {
  EXPECT_THROW(Pacer(Pacing::kRealtime, 0.0, kNsPerMs), Error);
  EXPECT_THROW(Pacer(Pacing::kRealtime, -1.0, kNsPerMs), Error);
}

TEST(LagWarner, WarnsPastThresholdAtMostOncePerInterval) {
  LagWarner warner(10 * kNsPerMs, kNsPerS);
  EXPECT_FALSE(warner.ShouldWarn(10 * kNsPerMs, 0));  // At the threshold: quiet.
  EXPECT_TRUE(warner.ShouldWarn(11 * kNsPerMs, 0));
  EXPECT_FALSE(warner.ShouldWarn(50 * kNsPerMs, kNsPerS - 1));
  EXPECT_TRUE(warner.ShouldWarn(50 * kNsPerMs, kNsPerS));
}

}  // namespace
}  // namespace sitlnet::coordinator

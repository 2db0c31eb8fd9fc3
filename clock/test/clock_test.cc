// The rounding rule of clock/clock.h, pinned with values worked out by hand from
//   wall(v) = origin + ceil(v / f),  virtual(w) = floor((w - origin) * f).
#include "clock/clock.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <ctime>
#include <limits>
#include <random>
#include <vector>

namespace sitlnet::clock {
namespace {

TEST(Timebase, FactorOneIsTheIdentityShiftedByTheOrigin) {
  Timebase timebase(1.0);
  timebase.Begin(1000);
  EXPECT_EQ(timebase.WallOf(0), 1000);
  EXPECT_EQ(timebase.WallOf(7), 1007);
  EXPECT_EQ(timebase.VirtualOf(1007), 7);
  EXPECT_EQ(timebase.VirtualOf(999), -1);
}

TEST(Timebase, QuarterSpeedTakesFourWallNanosecondsPerVirtualOne) {
  Timebase timebase(0.25);
  timebase.Begin(100);
  EXPECT_EQ(timebase.WallOf(1), 104);
  EXPECT_EQ(timebase.WallOf(kNsPerS), 100 + 4 * kNsPerS);
  // floor(w / 4): 7 wall ns after the origin, one virtual ns has fully come.
  EXPECT_EQ(timebase.VirtualOf(107), 1);
  EXPECT_EQ(timebase.VirtualOf(108), 2);
  EXPECT_EQ(timebase.VirtualOf(99), -1);  // floor(-0.25)
}

TEST(Timebase, DoubleSpeedRoundsWallInstantsUpAndVirtualTimesDown) {
  Timebase timebase(2.0);
  timebase.Begin(0);
  EXPECT_EQ(timebase.WallOf(1), 1);  // ceil(0.5): never before the virtual instant
  EXPECT_EQ(timebase.WallOf(3), 2);  // ceil(1.5)
  EXPECT_EQ(timebase.WallOf(4), 2);
  EXPECT_EQ(timebase.WallOf(-3), -1);  // ceil(-1.5)
  EXPECT_EQ(timebase.VirtualOf(2), 4);
  EXPECT_EQ(timebase.VirtualOf(kNsPerS), 2 * kNsPerS);
}

TEST(Timebase, ANonDyadicFactorIsExact) {
  // 0.1 as a double is 0.1000000000000000055511151231257827: 1 / f is just below 10.
  Timebase timebase(0.1);
  EXPECT_EQ(timebase.WallSpanOf(1), 10);
  EXPECT_EQ(timebase.VirtualSpanOf(10), 1);
  EXPECT_EQ(timebase.VirtualSpanOf(9), 0);
  EXPECT_EQ(timebase.WallSpanOf(kNsPerS), 10 * kNsPerS);
}

TEST(Timebase, RoundTripsNeverRunAheadOrFallBehind) {
  std::mt19937_64 rng(20261125);
  // Up to 30 days: at the slowest factor (1/1024) that is 84 years of wall time, within int64.
  std::uniform_int_distribution<TimeNs> times(-kNsPerS, 30LL * 24 * 3600 * kNsPerS);
  for (double factor : {0.25, 1.0, 2.0, 0.1, 0.3, 3.7, kMinRealtimeFactor, kMaxRealtimeFactor}) {
    Timebase timebase(factor);
    timebase.Begin(12345);
    for (int i = 0; i < 2000; ++i) {
      const TimeNs t = times(rng);
      // What is released at wall(v) is not early; what is read at w has come by w.
      EXPECT_GE(timebase.VirtualOf(timebase.WallOf(t)), t) << factor << " " << t;
      EXPECT_LE(timebase.WallOf(timebase.VirtualOf(t)), t) << factor << " " << t;
      // wall(v) is the FIRST such instant.
      EXPECT_LT(timebase.VirtualOf(timebase.WallOf(t) - 1), t) << factor << " " << t;
    }
  }
}

TEST(Timebase, LongRunsSaturateInsteadOfOverflowing) {
  const TimeNs max = std::numeric_limits<TimeNs>::max();
  Timebase half(2.0);
  EXPECT_EQ(half.WallSpanOf(max), max / 2 + 1);  // ceil((2^63 - 1) / 2) = 2^62
  EXPECT_EQ(half.VirtualSpanOf(max), max);       // 2 * max saturates
  Timebase quarter(0.25);
  EXPECT_EQ(quarter.WallSpanOf(max / 2), max);  // 4 * (max / 2) saturates
  EXPECT_EQ(quarter.VirtualSpanOf(max), max / 4);
}

TEST(Timebase, InstantsSaturateLikeSpans) {
  // Origins are CLOCK_MONOTONIC readings (here 1000 s of uptime). A wall instant beyond int64 is
  // "never", not a wrapped-around negative instant that would release at once.
  const TimeNs max = std::numeric_limits<TimeNs>::max();
  const TimeNs min = std::numeric_limits<TimeNs>::min();
  const TimeNs uptime = 1000 * kNsPerS;
  Timebase one(1.0);
  one.Begin(uptime);
  EXPECT_EQ(one.WallOf(max - uptime), max);  // Exactly representable: no saturation needed.
  EXPECT_EQ(one.WallOf(max), max);
  // The longest run a scenario may ask for (366 days) at the slowest factor ends 1024 years of
  // wall time later: never; and never late.
  const TimeNs year_ns = 366LL * 24 * 3600 * kNsPerS;
  Timebase slow(kMinRealtimeFactor);
  slow.Begin(uptime);
  EXPECT_EQ(slow.WallOf(year_ns), max);
  EXPECT_EQ(slow.LagNs(year_ns, max - 1), 0);
  EXPECT_EQ(slow.LagNs(0, max), max - uptime);
  // Far before the origin, and an origin far back.
  Timebase fast(kMaxRealtimeFactor);
  fast.Begin(max);
  EXPECT_EQ(fast.VirtualOf(min), min);
  fast.Begin(min);
  EXPECT_EQ(fast.WallOf(min), min);  // min + ceil(min / 1024)
  EXPECT_EQ(fast.LagNs(min, max), max);
  fast.BeginAt(max, min);  // min - ceil(max / 1024)
  EXPECT_EQ(fast.wall_origin_ns(), min);
}

TEST(Timebase, BeginAtMakesTheGivenVirtualTimeNow) {
  for (double factor : {0.25, 1.0, 0.3}) {
    Timebase timebase(factor);
    timebase.BeginAt(10 * kNsPerMs + 7, 5 * kNsPerS);
    EXPECT_EQ(timebase.VirtualOf(5 * kNsPerS), 10 * kNsPerMs + 7) << factor;
  }
  // Above factor 1 a wall nanosecond covers several virtual ones: odd virtual times fall
  // between two wall nanoseconds at factor 2, and "now" is the next one that has come.
  Timebase fast(2.0);
  fast.BeginAt(10 * kNsPerMs + 7, 5 * kNsPerS);
  EXPECT_EQ(fast.VirtualOf(5 * kNsPerS), 10 * kNsPerMs + 8);
  Timebase twice(2.0);
  twice.BeginAt(10, 1000);  // origin 1000 - ceil(10 / 2)
  EXPECT_EQ(twice.wall_origin_ns(), 995);
}

TEST(Timebase, LagIsHowFarTheWallClockIsPastTheVirtualInstant) {
  Timebase timebase(2.0);
  timebase.Begin(0);
  EXPECT_EQ(timebase.LagNs(10, 4), 0);
  EXPECT_EQ(timebase.LagNs(10, 5), 0);
  EXPECT_EQ(timebase.LagNs(10, 7), 2);
  Timebase slow(0.25);
  slow.Begin(0);
  EXPECT_EQ(slow.LagNs(kNsPerMs, 5 * kNsPerMs), kNsPerMs);
}

TEST(Timebase, RefusesFactorsItCannotConvertExactly) {
  for (double factor : {0.0, -1.0, 1e-300, 1e300, std::numeric_limits<double>::infinity(),
                        std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW(Timebase{factor}, Error) << factor;
    EXPECT_FALSE(CheckRealtimeFactor(factor).empty()) << factor;
  }
  EXPECT_TRUE(CheckRealtimeFactor(0.25).empty());
}

TEST(TickTimeNs, CarriesTheRemainderOfRatesThatDoNotDivideASecond) {
  EXPECT_EQ(TickTimeNs(1, 400), 2'500'000);
  EXPECT_EQ(TickTimeNs(1, 3), 333'333'333);  // floor(1e9 / 3)
  EXPECT_EQ(TickTimeNs(2, 3), 666'666'666);  // floor(2e9 / 3), not 2 * 333'333'333
  EXPECT_EQ(TickTimeNs(3, 3), kNsPerS);      // no drift after a whole second
  EXPECT_EQ(TickTimeNs(10'000'000'000, 1),
            std::numeric_limits<TimeNs>::max());  // 1e19 ns saturates
}

class RecordingClock final : public WallClock {
 public:
  TimeNs NowNs() override { return now_ns; }
  void SleepUntilNs(TimeNs wall_ns) override { slept_until.push_back(wall_ns); }
  TimeNs now_ns = 0;
  std::vector<TimeNs> slept_until;
};

TEST(SleepUntilVirtual, SleepsUntilTheWallInstantOfTheVirtualTime) {
  Timebase timebase(0.25);
  timebase.Begin(1000);
  RecordingClock wall;
  EXPECT_TRUE(SleepUntilVirtual(timebase, 3 * kNsPerMs, wall));
  ASSERT_EQ(wall.slept_until.size(), 1u);
  EXPECT_EQ(wall.slept_until[0], 1000 + 12 * kNsPerMs);
}

TEST(CalendarNsOfWall, IsTheRealtimeClockAtThatMonotonicInstant) {
  // Oracle: both clocks read here; they advance together (no one sets the host's time here).
  timespec realtime{};
  const TimeNs wall_now_ns = MonotonicNowNs();
  clock_gettime(CLOCK_REALTIME, &realtime);
  const TimeNs calendar_now_ns = TimeNs{realtime.tv_sec} * kNsPerS + realtime.tv_nsec;
  const TimeNs origin_ns = wall_now_ns - 3 * kNsPerS;
  EXPECT_NEAR(static_cast<double>(CalendarNsOfWall(origin_ns)),
              static_cast<double>(calendar_now_ns - 3 * kNsPerS), 0.1 * kNsPerS);
}

}  // namespace
}  // namespace sitlnet::clock

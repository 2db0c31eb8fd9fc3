// AutopilotRate's arithmetic and the AnswerMeter that fills it (summary.json's autopilot_rate,
// the progress line's rates; docs/run.md).
#include <gtest/gtest.h>

#include <thread>

#include "physics_mujoco/answer_meter.h"
#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {
namespace {

TEST(AutopilotRateTest, AnAutopilotAtItsOwnRateHasRatioOne) {
  // PX4 answering every 4 ms for 10 s: 2501 answers span 10 s.
  AutopilotRate rate;
  rate.answers = 2501;
  rate.first_answer_wall_ns = 5 * kNsPerS;
  rate.last_answer_wall_ns = 15 * kNsPerS;
  rate.nominal_hz = 250;
  EXPECT_DOUBLE_EQ(rate.AchievedHz(), 250);
  EXPECT_DOUBLE_EQ(rate.Ratio(), 1);
}

TEST(AutopilotRateTest, ASlowAutopilotHasItsShareOfTheNominalRate) {
  // ArduCopter asking for 1000 frames a second, answering 481 in 2 s of wall time.
  AutopilotRate rate{481, 0, 2 * kNsPerS, 1000};
  EXPECT_DOUBLE_EQ(rate.AchievedHz(), 240);
  EXPECT_DOUBLE_EQ(rate.Ratio(), 0.24);
}

TEST(AutopilotRateTest, UnderTwoAnswersOrNoNominalRateGiveZero) {
  EXPECT_EQ((AutopilotRate{}).AchievedHz(), 0);
  EXPECT_EQ((AutopilotRate{1, kNsPerS, kNsPerS, 250}).AchievedHz(), 0);
  EXPECT_EQ((AutopilotRate{1, kNsPerS, kNsPerS, 250}).Ratio(), 0);
  // Answers at one instant: no time between them, no rate (not infinity).
  EXPECT_EQ((AutopilotRate{5, kNsPerS, kNsPerS, 250}).AchievedHz(), 0);
  EXPECT_EQ((AutopilotRate{11, 0, kNsPerS, 0}).Ratio(), 0);
}

TEST(AutopilotRateTest, AnswersPerSecondOverAnInterval) {
  EXPECT_DOUBLE_EQ(AnswersPerSecond(1250, 5 * kNsPerS), 250);
  EXPECT_DOUBLE_EQ(AnswersPerSecond(1, kNsPerMs), 1000);
  EXPECT_EQ(AnswersPerSecond(0, 5 * kNsPerS), 0);  // A stalled autopilot.
  EXPECT_EQ(AnswersPerSecond(10, 0), 0);
  EXPECT_EQ(AnswersPerSecond(10, -kNsPerS), 0);
}

TEST(AutopilotRateTest, TheMeterKeepsTheFirstAndLastAnswerAndTheLatestNominalRate) {
  AnswerMeter meter;
  AutopilotRate rate = meter.Read();
  EXPECT_EQ(rate.answers, 0u);
  EXPECT_EQ(rate.first_answer_wall_ns, -1);
  EXPECT_EQ(rate.nominal_hz, 0);
  meter.Answered(0, 400, 10);  // Nothing answered: nothing changes.
  EXPECT_EQ(meter.Read().first_answer_wall_ns, -1);
  meter.Answered(1, 400, 100);
  meter.Answered(2, 1000, 300);  // SITL changed its rate.
  rate = meter.Read();
  EXPECT_EQ(rate.answers, 3u);
  EXPECT_EQ(rate.first_answer_wall_ns, 100);
  EXPECT_EQ(rate.last_answer_wall_ns, 300);
  EXPECT_EQ(rate.nominal_hz, 1000);
}

TEST(AutopilotRateTest, AReaderOnAnotherThreadSeesTimesAsNewAsTheCount) {
  // The writer stamps answer n at time n; a reader that sees count c sees a last time >= c.
  AnswerMeter meter;
  constexpr uint64_t kAnswers = 200000;
  std::thread writer([&] {
    for (uint64_t n = 1; n <= kAnswers; ++n) meter.Answered(1, 250, static_cast<TimeNs>(n));
  });
  uint64_t seen = 0;
  while (seen < kAnswers) {
    const AutopilotRate rate = meter.Read();
    ASSERT_GE(rate.answers, seen);
    if (rate.answers > 0) {
      ASSERT_GE(rate.last_answer_wall_ns, static_cast<TimeNs>(rate.answers));
    }
    seen = rate.answers;
  }
  writer.join();
}

}  // namespace
}  // namespace sitlnet::physics

#include "run_formats/run_formats.h"

#include <gtest/gtest.h>

namespace sitlnet::run_formats {
namespace {

constexpr TimeNs kS = kNsPerS;

TEST(ConnectivityTest, IsolatedRobotsAreTheirOwnComponents) {
  ConnectivityTracker tracker(3, kS, kS);
  tracker.Heard(kS / 2, 0, 1);
  const auto samples = tracker.Finish(kS);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].components, 2);
  EXPECT_EQ(samples[0].component_of, (std::vector<int>{0, 0, 2}));
}

TEST(ConnectivityTest, SplitsWhenLinksFallSilentAndReunites) {
  // Robots 0-1 and 2-3 talk all along; 1-2 only before 3 s and after 7 s.
  ConnectivityTracker tracker(4, 2 * kS, kS);
  for (TimeNs t = 0; t <= 10 * kS; t += kS / 10) {
    tracker.Heard(t, 0, 1);
    tracker.Heard(t, 3, 2);
    if (t < 3 * kS || t > 7 * kS) tracker.Heard(t, 1, 2);
  }
  const auto samples = tracker.Finish(10 * kS);
  ASSERT_EQ(samples.size(), 10u);
  EXPECT_EQ(samples[1].components, 1);  // t = 2 s
  EXPECT_EQ(samples[3].components, 1);  // t = 4 s: 1-2 last heard at 2.9 s, within 2 s
  EXPECT_EQ(samples[4].components, 2);  // t = 5 s: 2.1 s of silence
  EXPECT_EQ(samples[4].component_of, (std::vector<int>{0, 0, 2, 2}));
  EXPECT_EQ(samples[6].components, 2);  // t = 7 s
  EXPECT_EQ(samples[7].components, 1);  // t = 8 s: heard again since 7.1 s
}

TEST(ConnectivityTest, ADeliveryAtASampleInstantCountsForThatSample) {
  ConnectivityTracker tracker(2, kS / 2, kS);
  tracker.Heard(kS, 0, 1);  // At the first sample's instant: linked at t = 1 s.
  tracker.Heard(3 * kS, 1, 0);
  const auto samples = tracker.Finish(3 * kS);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[0].components, 1);
  EXPECT_EQ(samples[1].components, 2);  // 1 s of silence > the 0.5 s window
  EXPECT_EQ(samples[2].components, 1);
}

}  // namespace
}  // namespace sitlnet::run_formats

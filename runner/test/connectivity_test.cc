#include "runner/connectivity.h"

#include <gtest/gtest.h>

namespace sitlnet::runner {
namespace {

constexpr TimeNs kS = kNsPerS;

TEST(ConnectivityTest, IsolatedRobotsAreTheirOwnComponents) {
  const auto samples = ConnectivityOverTime(3, {{kS / 2, 0, 1}}, kS, kS, kS);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].components, 2);
  EXPECT_EQ(samples[0].component_of, (std::vector<int>{0, 0, 2}));
}

TEST(ConnectivityTest, SplitsWhenLinksFallSilentAndReunites) {
  // Robots 0-1 and 2-3 talk all along; 1-2 only before 3 s and after 7 s.
  std::vector<LinkEvent> events;
  for (TimeNs t = 0; t <= 10 * kS; t += kS / 10) {
    events.push_back({t, 0, 1});
    events.push_back({t, 3, 2});
    if (t < 3 * kS || t > 7 * kS) events.push_back({t, 1, 2});
  }
  const auto samples = ConnectivityOverTime(4, events, 2 * kS, kS, 10 * kS);
  ASSERT_EQ(samples.size(), 10u);
  EXPECT_EQ(samples[1].components, 1);  // t = 2 s
  EXPECT_EQ(samples[3].components, 1);  // t = 4 s: 1-2 last heard at 2.9 s, within 2 s
  EXPECT_EQ(samples[4].components, 2);  // t = 5 s: 2.1 s of silence
  EXPECT_EQ(samples[4].component_of, (std::vector<int>{0, 0, 2, 2}));
  EXPECT_EQ(samples[6].components, 2);  // t = 7 s
  EXPECT_EQ(samples[7].components, 1);  // t = 8 s: heard again since 7.1 s
}

}  // namespace
}  // namespace sitlnet::runner

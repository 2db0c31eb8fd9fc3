#include "coordinator/link_meter.h"

#include <gtest/gtest.h>

namespace sitlnet::coordinator {
namespace {

TEST(LinkMeter, CountsFinishedRoundTripsWithNearestRankPercentilesAndTheirBytes) {
  LinkMeter meter;
  EXPECT_EQ(meter.Stats().round_trips, 0);
  EXPECT_EQ(meter.Stats().BytesUpPerRoundTrip(), 0);
  // 100 round trips of 1..100 us, each a 100-byte START answered by 30 + 200 bytes.
  for (TimeNs k = 1; k <= 100; ++k) {
    meter.StartSent(1'000'000 * k, 100);
    meter.Received(30);
    meter.Received(200);
    meter.EndReceived(1'000'000 * k + k * kNsPerUs);
  }
  meter.StartSent(500'000'000, 100);  // Interrupted: its END never came.
  meter.Received(30);
  const LinkStats stats = meter.Stats();
  EXPECT_EQ(stats.round_trips, 100);
  EXPECT_EQ(stats.round_trip_p50_ns, 50 * kNsPerUs);
  EXPECT_EQ(stats.round_trip_p99_ns, 99 * kNsPerUs);
  EXPECT_EQ(stats.round_trip_max_ns, 100 * kNsPerUs);
  EXPECT_EQ(stats.bytes_down, 100 * 100);
  EXPECT_EQ(stats.bytes_up, 100 * 230);
  EXPECT_EQ(stats.BytesDownPerRoundTrip(), 100);
  EXPECT_EQ(stats.BytesUpPerRoundTrip(), 230);
}

}  // namespace
}  // namespace sitlnet::coordinator

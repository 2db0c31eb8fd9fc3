// Frame exchange details that decide agreement with ns-3 3.37: queue size,
// drop policy and expiry (WifiMacQueue), the rate of group-addressed frames
// (GetNonUnicastMode), control-response rates, and DIFS after an ACK timeout
// (ChannelAccessManager::GetAccessGrantStart).
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::MakeEthernetFrame;

constexpr MacAddress kBroadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

TEST(FrameExchangeTest, QueueLimitCountsTheFrameInService) {
  // ns-3's WifiMacQueue keeps the MPDU being sent in the queue, so MaxSize
  // covers it: a limit of 2 holds the frame in service and one more.
  MediumConfig config;
  config.queue_limit_frames = 2;
  Medium medium(config);
  const StationId a = medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  const auto frame = MakeEthernetFrame(RobotMac(1), RobotMac(0), 500);
  for (int i = 0; i < 5; ++i) medium.SubmitFrame(a, frame, 0);
  std::vector<Delivery> out;
  medium.AdvanceTo(kNsPerS, &out);
  EXPECT_EQ(medium.counters(a).queue_drops, 3u);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(medium.counters(a).frames_submitted, 5u);
}

TEST(FrameExchangeTest, DefaultQueueHoldsNs3s500Frames) {
  Medium medium(MediumConfig{});
  const StationId a = medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  const auto frame = MakeEthernetFrame(RobotMac(1), RobotMac(0), 100);
  for (int i = 0; i < 600; ++i) medium.SubmitFrame(a, frame, 0);
  medium.AdvanceTo(0, nullptr);
  EXPECT_EQ(medium.queued_frames(a), 499u);  // Plus the one in service.
  EXPECT_EQ(medium.counters(a).queue_drops, 100u);
}

TEST(FrameExchangeTest, FramesOlderThanMaxDelayExpireOnInsertAndAtAccess) {
  // ns-3 3.37 removes frames older than WifiMacQueue's MaxDelay when a frame
  // arrives at a full queue (Insert) and at every channel access
  // (FrameExchangeManager::StartTransmission), the frame being sent included.
  // 11b at 1 Mb/s: station B holds the medium with an 18.6 ms broadcast from
  // t = 0; A's three frames (queue limit 3) wait behind it.
  MediumConfig config;
  config.standard = Standard::k80211b;
  config.rate_mbps = 1;
  config.queue_limit_frames = 3;
  config.queue_max_delay_ns = 1 * kNsPerMs;
  Medium medium(config);
  const StationId a = medium.AddStation(RobotMac(0), {});
  const StationId b = medium.AddStation(RobotMac(1), {1, 0, 0});
  medium.SubmitFrame(b, MakeEthernetFrame(kBroadcast, RobotMac(1), 2290), 0);
  const auto frame = MakeEthernetFrame(RobotMac(1), RobotMac(0), 100);
  for (int i = 0; i < 3; ++i) medium.SubmitFrame(a, frame, 100 * kNsPerUs);
  medium.SubmitFrame(a, frame, 500 * kNsPerUs);   // Full, nothing expired: dropped.
  medium.SubmitFrame(a, frame, 1200 * kNsPerUs);  // Full: the two waiting expire, it stays.
  medium.AdvanceTo(1300 * kNsPerUs, nullptr);
  EXPECT_EQ(medium.counters(a).queue_drops, 3u);  // One arrival at a full queue, two expired.
  EXPECT_EQ(medium.counters(a).queue_expired, 2u);
  EXPECT_EQ(medium.queued_frames(a), 1u);
  // At A's access after the broadcast both remaining frames are too old.
  std::vector<Delivery> out;
  medium.AdvanceTo(30 * kNsPerMs, &out);
  EXPECT_EQ(medium.counters(a).queue_expired, 4u);
  EXPECT_EQ(medium.counters(a).queue_drops, 5u);
  EXPECT_EQ(medium.counters(a).data_tx, 0u);
  EXPECT_EQ(out.size(), 1u);  // B's broadcast only.
}

TEST(FrameExchangeTest, RetryCountIsPerStationAcrossExpiredFrames) {
  // The short retry count is the station's (10.3.4.4; ns-3's SSRC): it counts
  // failures until a success or a discard, not per frame. Here every frame
  // expires (1 ms) before its retry (a 2 ms DATA to an absent station, CW 0)
  // and a fresh one goes instead; every 7th failure still discards a frame.
  MediumConfig config;
  config.rate_mbps = 6;
  config.cw_min = 0;
  config.cw_max = 0;
  config.queue_max_delay_ns = 1 * kNsPerMs;
  Medium medium(config);
  const StationId a = medium.AddStation(RobotMac(0), {});
  const auto frame = MakeEthernetFrame(RobotMac(1), RobotMac(0), 1500);
  for (TimeNs t = 0; t < 45 * kNsPerMs; t += 500 * kNsPerUs) medium.SubmitFrame(a, frame, t);
  medium.AdvanceTo(45 * kNsPerMs, nullptr);
  const StationCounters& c = medium.counters(a);
  EXPECT_EQ(c.retries, 0u);  // Never the same frame twice.
  EXPECT_GE(c.data_tx, 14u);
  EXPECT_EQ(c.lost_retry_limit, c.tx_failures / 7);
}

TEST(FrameExchangeTest, GroupFramesGoAtTheLowestBasicRateWithoutAck) {
  // The flocking beacon: a PSDU of 264 bytes (242-byte Ethernet
  // frame) lasts 60 us at 54 Mb/s but 376 us at 6 Mb/s (17.4.3); 11g sends it
  // at 1 Mb/s DSSS, 192 + 8 x 264 = 2304 us. Configurable per scenario.
  struct Case {
    Standard standard;
    std::optional<double> group_rate_mbps;
    double expected_rate_mbps;
    TimeNs expected_airtime_ns;
  };
  for (const Case& c : {Case{Standard::k80211a, std::nullopt, 6, 376 * kNsPerUs},
                        Case{Standard::k80211a, 54, 54, 60 * kNsPerUs},
                        Case{Standard::k80211g, std::nullopt, 1, 2304 * kNsPerUs}}) {
    MediumConfig config;
    config.standard = c.standard;
    config.group_rate_mbps = c.group_rate_mbps;
    Medium medium(config);
    medium.AddStation(RobotMac(0), {});
    medium.AddStation(RobotMac(1), {1, 0, 0});
    medium.EnableTrace(true);
    medium.SubmitFrame(0, MakeEthernetFrame(kBroadcast, RobotMac(0), 242 - 14), 0);
    std::vector<Delivery> out;
    medium.AdvanceTo(10 * kNsPerMs, &out);
    const std::vector<TxRecord> txs = DrainTransmissions(medium);
    ASSERT_EQ(txs.size(), 1u);  // No ACK, no retry.
    EXPECT_EQ(txs[0].rate_mbps, c.expected_rate_mbps);
    EXPECT_EQ(txs[0].end_ns - txs[0].start_ns, c.expected_airtime_ns);
    EXPECT_EQ(out.size(), 1u);
  }
}

TEST(FrameExchangeTest, ElevenMbpsDsssFrameIsAcknowledgedAtElevenMbps) {
  MediumConfig config;
  config.standard = Standard::k80211b;
  config.rate_mbps = 11;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  medium.EnableTrace(true);
  medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 1500), 0);
  medium.AdvanceTo(10 * kNsPerMs, nullptr);
  const std::vector<TxRecord> txs = DrainTransmissions(medium);
  ASSERT_EQ(txs.size(), 2u);
  EXPECT_EQ(txs[1].kind, FrameKind::kAck);
  EXPECT_EQ(txs[1].rate_mbps, 11);
  EXPECT_EQ(txs[1].start_ns, txs[0].end_ns + 10 * kNsPerUs);  // SIFS.
  EXPECT_EQ(txs[1].end_ns - txs[1].start_ns, 203 * kNsPerUs);
}

TEST(FrameExchangeTest, DifsFollowsAnExpiredAckTimeout) {
  // No receiver, CW fixed at 0 so no backoff slot: the retry starts when the
  // ACK timeout (SIFS + slot + 20 us PHY header = 45 us after the DATA) has
  // expired and DIFS (34 us) has followed it, as ns-3's GetAccessGrantStart
  // treats the timeout end like the end of a busy period: 79 us after.
  MediumConfig config;
  config.cw_min = 0;
  config.cw_max = 0;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {});
  medium.EnableTrace(true);
  medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 100), 0);
  medium.AdvanceTo(10 * kNsPerMs, nullptr);
  const std::vector<TxRecord> txs = DrainTransmissions(medium);
  ASSERT_EQ(txs.size(), 7u);  // dot11ShortRetryLimit attempts.
  for (size_t i = 1; i < txs.size(); ++i) {
    EXPECT_EQ(txs[i].start_ns - txs[i - 1].end_ns, (45 + 34) * kNsPerUs) << i;
  }
}

}  // namespace
}  // namespace sitlnet::mac

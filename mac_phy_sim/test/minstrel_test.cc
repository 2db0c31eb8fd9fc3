// Minstrel (ns-3 3.37's MinstrelWifiManager). Oracle: ns-3's arithmetic in
// minstrel-wifi-manager.cc, worked by hand below (EWMA, throughput ranking,
// retry counts within 6 ms, the retry chain, the sample table's shape); and
// on a medium, the same seed gives the same choices. Its throughput against
// distance is compared with ns-3's in the side-by-side matrix.
#include "mac_phy_sim/minstrel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::LinkDataFrames;
using testing::MakeEthernetFrame;

// 802.11a's eight rates with a 1200-byte PSDU: 20 us of preamble and header plus 4 us per
// symbol of ceil((16 + 8 x 1200 + 6) / bits per symbol) (IEEE 802.11-2016 17.4.3).
MinstrelPhy Phy11a() {
  MinstrelPhy phy;
  for (int bits_per_symbol : {24, 36, 48, 72, 96, 144, 192, 216}) {
    const int symbols = (16 + 8 * 1200 + 6 + bits_per_symbol - 1) / bits_per_symbol;
    phy.perfect_tx_ns.push_back((20 + 4 * symbols) * kNsPerUs);
  }
  phy.sifs_ns = 16 * kNsPerUs;
  phy.slot_ns = 9 * kNsPerUs;
  phy.ack_tx_ns = 44 * kNsPerUs;
  return phy;
}

TEST(MinstrelTest, PerfectTimesAndRetryCountsFitSixMilliseconds) {
  Minstrel minstrel(Phy11a(), MediumConfig::Minstrel{}, 1);
  const MinstrelRemote r = minstrel.NewRemote(0);
  EXPECT_EQ(r.rates[0].perfect_tx_ns, 1624 * kNsPerUs);  // 6 Mb/s: 401 symbols.
  EXPECT_EQ(r.rates[7].perfect_tx_ns, 200 * kNsPerUs);   // 54 Mb/s: 45 symbols.
  // One attempt is DATA + SIFS + 44 us; retry k adds half of CW 31, 64, 130, 262, 526 slots.
  // 54 Mb/s: 4 retries take 5 x 260 + 9 x (15.5 + 32 + 65 + 131) = 3491.5 us, 5 take 6118.5.
  EXPECT_EQ(minstrel.UnicastTimeNs(200 * kNsPerUs, 4), 3491500);
  EXPECT_EQ(minstrel.UnicastTimeNs(200 * kNsPerUs, 5), 6118500);
  EXPECT_EQ(r.rates[7].retry_count, 4u);
  // 6 Mb/s: 2 retries take 3 x 1684 + 9 x 47.5 = 5479.5 us, 3 take 7748.5.
  EXPECT_EQ(r.rates[0].retry_count, 2u);
  EXPECT_EQ(r.rates[0].sample_limit, -1);
  EXPECT_EQ(r.tx_rate, 0);  // Starts at the first supported rate.
}

TEST(MinstrelTest, EwmaAndThroughputFollowNs3sIntegerArithmetic) {
  Minstrel minstrel(Phy11a(), MediumConfig::Minstrel{}, 1);
  MinstrelRemote r = minstrel.NewRemote(0);
  r.rates[7].attempts = 10;
  r.rates[7].successes = 5;
  minstrel.UpdateStats(r, 99 * kNsPerMs);  // Before the first 100 ms: nothing.
  EXPECT_EQ(r.rates[7].ewma_probability, 0u);
  minstrel.UpdateStats(r, 100 * kNsPerMs);
  // First interval: the EWMA starts at the interval's 5 / 10 x 18000.
  EXPECT_EQ(r.rates[7].probability, 9000u);
  EXPECT_EQ(r.rates[7].ewma_probability, 9000u);
  EXPECT_EQ(r.rates[7].throughput, 9000u * (1000000 / 200));
  EXPECT_EQ(r.next_stats_update_ns, 200 * kNsPerMs);
  r.rates[7].attempts = 10;
  r.rates[7].successes = 10;
  minstrel.UpdateStats(r, 200 * kNsPerMs);
  // (18000 x 25 + 9000 x 75) / 100.
  EXPECT_EQ(r.rates[7].ewma_probability, 11250u);
  EXPECT_EQ(r.rates[7].success_history, 15u);
  EXPECT_EQ(r.rates[7].attempt_history, 20u);
  EXPECT_EQ(r.rates[6].samples_skipped, 2);  // Never tried.
}

TEST(MinstrelTest, RanksByThroughputAndPrefersReliableRates) {
  Minstrel minstrel(Phy11a(), MediumConfig::Minstrel{}, 1);
  MinstrelRemote r = minstrel.NewRemote(0);
  // 54 Mb/s at 50 %: 9000 x 5000 = 45e6. 36 Mb/s (288 us) at 100 %: 18000 x 3472 = 62.5e6.
  // 48 Mb/s (224 us) at 20 %: 3600 x 4464 = 16.1e6.
  r.rates[7] .attempts = 10, r.rates[7].successes = 5;
  r.rates[5].attempts = 10, r.rates[5].successes = 10;
  r.rates[6].attempts = 10, r.rates[6].successes = 2;
  minstrel.UpdateStats(r, 100 * kNsPerMs);
  EXPECT_EQ(r.max_tp_rate, 5);
  EXPECT_EQ(r.max_tp_rate2, 7);
  EXPECT_EQ(r.max_prob_rate, 5);  // Above 95 % and the fastest such.
  EXPECT_EQ(r.tx_rate, 5);        // Raised to the best (ns-3 compares indices).
  // Above 95 % or below 10 %: at most 2 tries and 4 samples; between: the full count.
  EXPECT_EQ(r.rates[5].sample_limit, 4);
  EXPECT_EQ(r.rates[5].adjusted_retry_count, 2u);
  EXPECT_EQ(r.rates[7].sample_limit, -1);
  EXPECT_EQ(r.rates[7].adjusted_retry_count, r.rates[7].retry_count);
}

TEST(MinstrelTest, RetryChainGoesBestSecondProbabilityThenLowest) {
  Minstrel minstrel(Phy11a(), MediumConfig::Minstrel{}, 1);
  MinstrelRemote r = minstrel.NewRemote(0);
  r.max_tp_rate = 7;
  r.max_tp_rate2 = 6;
  r.max_prob_rate = 3;
  for (int i : {7, 6, 3}) r.rates[i].adjusted_retry_count = 2;
  r.tx_rate = 7;
  // ns-3's UpdateRate: retry k < 2 at the best, <= 4 the second, <= 6 the probable, then rate 0.
  std::vector<int> chain;
  for (int k = 0; k < 8; ++k) {
    minstrel.ReportDataFailed(r);
    chain.push_back(r.tx_rate);
  }
  EXPECT_EQ(chain, (std::vector<int>{7, 6, 6, 6, 3, 3, 0, 0}));
  // The chain is 2 + 2 + 2 + rate 0's count (2 at 6 Mb/s) long.
  EXPECT_EQ(Minstrel::CountRetries(r), 8u);
  EXPECT_FALSE(Minstrel::NeedRetransmission(r));
  minstrel.ReportFinalDataFailed(r, 0);
  EXPECT_EQ(r.long_retry, 0u);
  EXPECT_EQ(r.retry, 8u);
  EXPECT_EQ(r.total_packets, 1);
}

TEST(MinstrelTest, SampleTableColumnsArePermutationsDrawnFromTheSeed) {
  MediumConfig::Minstrel config;
  Minstrel a(Phy11a(), config, 7), b(Phy11a(), config, 7), c(Phy11a(), config, 8);
  const MinstrelRemote ra = a.NewRemote(0), rb = b.NewRemote(0), rc = c.NewRemote(0);
  EXPECT_EQ(ra.sample_table, rb.sample_table);
  EXPECT_NE(ra.sample_table, rc.sample_table);
  for (int col = 0; col < config.sample_columns; ++col) {
    std::vector<int> column;
    for (const auto& row : ra.sample_table) column.push_back(row[col]);
    std::sort(column.begin(), column.end());
    std::vector<int> all(8);
    std::iota(all.begin(), all.end(), 0);
    EXPECT_EQ(column, all) << col;
  }
  // A second destination of the same sender draws its own table from the same stream.
  EXPECT_NE(a.NewRemote(0).sample_table, ra.sample_table);
}

// DATA rates of a saturated 11a link over `duration_ns` with Minstrel.
std::vector<double> MinstrelRates(double distance_m, uint64_t seed, TimeNs duration_ns) {
  MediumConfig config;
  config.rate_control = MediumConfig::RateControl::kMinstrel;
  config.seed = seed;
  std::vector<double> rates;
  for (const TxRecord& tx : LinkDataFrames(config, distance_m, 250 * kNsPerUs, duration_ns)) {
    rates.push_back(tx.rate_mbps);
  }
  return rates;
}

TEST(MinstrelTest, OnAMediumLearnsTheLinkAndRepeatsItsChoicesForASeed) {
  // 5 m: SNR 45 dB, every rate succeeds; after a few updates the best is 54 Mb/s. Every
  // other rate is slower, so look-around frames are deferred: they go first at the best rate
  // and, as that succeeds, never reach the sampled one (ns-3's FindRate and retry chain).
  // Starts at 6 Mb/s (the first supported rate).
  const std::vector<double> near = MinstrelRates(5, 1, 600 * kNsPerMs);
  ASSERT_GT(near.size(), 1000u);
  EXPECT_EQ(near.front(), 6);
  const auto late = near.end() - 500;
  const auto at_54 = std::count(late, near.end(), 54.0);
  EXPECT_EQ(at_54, 500);
  EXPECT_EQ(near, MinstrelRates(5, 1, 600 * kNsPerMs));
  EXPECT_NE(near, MinstrelRates(5, 2, 600 * kNsPerMs));
  // 45 m: 54 Mb/s never gets through (SNR about 15 dB); the link settles lower.
  const std::vector<double> far = MinstrelRates(45, 1, 600 * kNsPerMs);
  ASSERT_GT(far.size(), 100u);
  const auto far_late = far.end() - 100;
  EXPECT_LT(std::count(far_late, far.end(), 54.0), 20);
}

// One frame to a station out of reach (nothing is ever received), with or without RTS.
std::vector<TraceEvent> UnansweredFrame(MediumConfig::RateControl rate_control, bool rts) {
  MediumConfig config;
  config.rate_control = rate_control;
  config.rts_threshold_bytes = rts ? 1 : 0;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {500, 0, 0});
  medium.EnableTrace(true);
  medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 500), 0);
  medium.AdvanceTo(2 * kNsPerS, nullptr);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  return trace;
}

int Count(const std::vector<TraceEvent>& trace, FrameKind kind) {
  return static_cast<int>(std::count_if(trace.begin(), trace.end(), [&](const TraceEvent& e) {
    return e.tx && e.tx->kind == kind;
  }));
}

TEST(MinstrelTest, RetryChainReplacesTheRetryLimit) {
  // Constant rate: 7 attempts (dot11ShortRetryLimit), then a retry-limit drop.
  const std::vector<TraceEvent> constant = UnansweredFrame(MediumConfig::RateControl::kConstant, false);
  EXPECT_EQ(Count(constant, FrameKind::kData), 7);
  // Minstrel before any statistics: every stage is 6 Mb/s with 2 retries (worked above), so
  // ns-3's CountRetries is 2 + 2 + 2 + 2 and the frame goes 8 times (DoNeedRetransmission).
  const std::vector<TraceEvent> minstrel = UnansweredFrame(MediumConfig::RateControl::kMinstrel, false);
  EXPECT_EQ(Count(minstrel, FrameKind::kData), 8);
  ASSERT_TRUE(minstrel.back().drop.has_value());
  EXPECT_EQ(minstrel.back().drop->reason, DropReason::kRetryLimit);
  // RTS failures do not count towards the chain (only DATA failures raise ns-3's m_longRetry):
  // the RTS goes again and again until the frame expires in the queue (500 ms).
  const std::vector<TraceEvent> rts = UnansweredFrame(MediumConfig::RateControl::kMinstrel, true);
  EXPECT_GT(Count(rts, FrameKind::kRts), 20);
  EXPECT_EQ(Count(rts, FrameKind::kData), 0);
  ASSERT_TRUE(rts.back().drop.has_value());
  EXPECT_EQ(rts.back().drop->reason, DropReason::kQueueExpired);
}

}  // namespace
}  // namespace sitlnet::mac

// Minstrel-HT (ns-3 3.37's MinstrelHtWifiManager). Oracle: ns-3's arithmetic in
// minstrel-ht-wifi-manager.cc and ht-phy.cc, worked by hand below (group ids and
// the global index, first-MPDU times, retry counts within 6 ms, EWMA, throughput
// ranking, the retry chain, the sample table's shape); on a medium, the same seed
// gives the same choices. Its throughput against distance is compared with
// ns-3's in the side-by-side matrix.
#include "mac_phy_sim/minstrel_ht.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>
#include <vector>

#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::LinkDataFrames;
using testing::MakeEthernetFrame;

TEST(MinstrelHtTest, GroupIdsAndIndicesAreNs3s) {
  // GetHtGroupId: 8 x width index + 4 x GI index + streams - 1.
  EXPECT_EQ(MinstrelHtGroupId(1, false, 20), 0);
  EXPECT_EQ(MinstrelHtGroupId(2, false, 20), 1);
  EXPECT_EQ(MinstrelHtGroupId(1, true, 20), 4);
  EXPECT_EQ(MinstrelHtGroupId(1, false, 40), 8);
  EXPECT_EQ(MinstrelHtGroupId(2, true, 40), 13);
  // GetVhtGroupId: after the 16 HT groups, 16 x width index + 8 x GI index + streams - 1.
  EXPECT_EQ(MinstrelVhtGroupId(1, false, 20), 16);
  EXPECT_EQ(MinstrelVhtGroupId(2, true, 40), 16 + 16 + 8 + 1);
  EXPECT_EQ(MinstrelVhtGroupId(1, false, 80), 48);
  EXPECT_EQ(MinstrelVhtGroupId(8, true, 160), 79);
}

// HT-mixed PPDU, one stream: 16 us L-STF/L-LTF, 4 us L-SIG, 8 us HT-SIG, 4 us HT-STF, 4 us
// HT-LTF = 36 us. HtPhy::GetPayloadDuration of a first MPDU: (16 + 8 x 1200 + 6) / N_DBPS
// symbols of 4 us, not rounded up (N_DBPS 26 at MCS 0, 260 at MCS 7).
TEST(MinstrelHtTest, FirstAndMiddleMpduTimesAreFractionalSymbols) {
  const Standard n = Standard::k80211n5GHz;
  const PhyMode mcs0 = McsModeFor(n, 0, 1, 20, false);
  const PhyMode mcs7 = McsModeFor(n, 7, 1, 20, false);
  const PhyHeader header = HeaderFor(n, mcs7, false);
  EXPECT_EQ(header.preamble_and_header_ns, 36000);
  EXPECT_EQ(AmpduMpduDurationNs(mcs7, header, 1200, true), 36000 + 9622 * 4000 / 260);  // 184030
  EXPECT_EQ(AmpduMpduDurationNs(mcs0, header, 1200, true), 36000 + 1480307);
  // A middle MPDU carries no SERVICE or tail bits, but ns-3 adds the preamble all the same.
  EXPECT_EQ(AmpduMpduDurationNs(mcs7, header, 1200, false), 36000 + 9600 * 4000 / 260);
}

// One 802.11n 5 GHz group (1 stream, long GI, 20 MHz), or with `two_streams` a second one.
MinstrelHtPhy PhyHt20(bool two_streams = false) {
  const Standard n = Standard::k80211n5GHz;
  MinstrelHtPhy phy;
  phy.rates_per_group = 8;
  phy.groups.resize(kMinstrelHtGroups);
  for (int streams = 1; streams <= (two_streams ? 2 : 1); ++streams) {
    MinstrelHtGroup& group = phy.groups[MinstrelHtGroupId(streams, false, 20)];
    group.supported = true;
    group.streams = streams;
    group.rate_supported.assign(8, true);
    for (int rate = 0; rate < 8; ++rate) {
      const PhyMode mode = McsModeFor(n, (streams - 1) * 8 + rate, streams, 20, false);
      const PhyHeader header = HeaderFor(n, mode, false);
      group.first_mpdu_ns.push_back(AmpduMpduDurationNs(mode, header, 1200, true));
      group.middle_mpdu_ns.push_back(AmpduMpduDurationNs(mode, header, 1200, false));
    }
  }
  phy.slot_ns = 9 * kNsPerUs;
  phy.sifs_ns = 16 * kNsPerUs;
  phy.block_ack_tx_ns = 68 * kNsPerUs;
  return phy;
}

TEST(MinstrelHtTest, RetryCountsFitSixMillisecondsOnceARateWorks) {
  MinstrelHt minstrel(PhyHt20(), MediumConfig::Minstrel{}, 1);
  MinstrelHtRemote r = minstrel.NewRemote(0);
  // Before any success (EWMA below 1 %): one try per rate.
  for (int rate = 0; rate < 8; ++rate) EXPECT_EQ(r.rates[rate].retry_count, 1u) << rate;
  // CalculateRetransmits with 9 us slots and SIFS + BlockAck = 84 us: contention 7 + 16 slots
  // for the first two tries, then 33, 67, 135, 271 slots. MCS 7 (184.03 us): 743.06 us after
  // two, then 1308.09, 2179.12, 3662.15 (5 tries), 6369.18 us (over 6 ms): 5.
  // MCS 0 (1516.307 us): 3407.6, then 5304.9 (3 tries), 7508.2 us: 3.
  for (int rate : {0, 7}) {
    r.rates[rate].ewma_probability = 50;
    r.rates[rate].retry_updated = false;
    minstrel.CalculateRetransmits(r, rate);
  }
  EXPECT_EQ(r.rates[7].retry_count, 5u);
  EXPECT_EQ(r.rates[0].retry_count, 3u);
  // Computed once per statistics update.
  r.rates[7].ewma_probability = 0;
  minstrel.CalculateRetransmits(r, 7);
  EXPECT_EQ(r.rates[7].retry_count, 5u);
}

TEST(MinstrelHtTest, EwmaThroughputAndRankingFollowNs3) {
  MinstrelHt minstrel(PhyHt20(), MediumConfig::Minstrel{}, 1);
  MinstrelHtRemote r = minstrel.NewRemote(0);
  // First interval: MCS 7 7 of 10 (70 %), MCS 5 10 of 10 (100 %), MCS 6 1 of 20 (5 %).
  r.rates[7].attempts = 10;
  r.rates[7].successes = 7;
  r.rates[7].success_history = 0;
  r.rates[5].attempts = r.rates[5].successes = 10;
  r.rates[6].attempts = 20;
  r.rates[6].successes = 1;
  minstrel.UpdateStats(r, 50 * kNsPerMs);
  EXPECT_EQ(r.next_stats_update_ns, 100 * kNsPerMs);
  EXPECT_EQ(r.rates[7].ewma_probability, 70);  // The first value as it is.
  EXPECT_EQ(r.rates[6].ewma_probability, 5);
  EXPECT_EQ(r.rates[6].throughput, 0);  // Below 10 %: no throughput.
  const double mcs7_s = 184030e-9, mcs5_s = (36000 + 9622 * 4000 / 208) * 1e-9;
  EXPECT_DOUBLE_EQ(r.rates[7].throughput, 70 / mcs7_s);
  EXPECT_DOUBLE_EQ(r.rates[5].throughput, 90 / mcs5_s);  // Capped at 90 %.
  // 90 / 221.038 us > 70 / 184.03 us: MCS 5 is best, MCS 7 second; the best probability above
  // 75 % with the highest throughput is MCS 5.
  EXPECT_EQ(r.max_tp_rate, 5);
  EXPECT_EQ(r.max_tp_rate2, 7);
  EXPECT_EQ(r.max_prob_rate, 5);
  // Second interval: MCS 7 9 of 10: (90 x 25 + 70 x 75) / 100 = 75 %, and 75 / 184.03 us =
  // 407,542/s just beats MCS 5's 90 / 221.038 us = 407,169/s (kept: no attempts, one skipped
  // update). The best-probability rate stays MCS 5: 75 % is not above 75 %.
  r.rates[7].attempts = 10;
  r.rates[7].successes = 9;
  minstrel.UpdateStats(r, 100 * kNsPerMs);
  EXPECT_DOUBLE_EQ(r.rates[7].ewma_probability, 75);
  EXPECT_EQ(r.rates[5].samples_skipped, 1u);
  EXPECT_EQ(r.max_tp_rate, 7);
  EXPECT_EQ(r.max_tp_rate2, 5);
  EXPECT_EQ(r.max_prob_rate, 5);
  // Third: MCS 7 all 10: (100 x 25 + 75 x 75) / 100 = 81.25 %. Both above 75 %: the faster of
  // them is the best-probability rate too.
  r.rates[7].attempts = r.rates[7].successes = 10;
  minstrel.UpdateStats(r, 150 * kNsPerMs);
  EXPECT_DOUBLE_EQ(r.rates[7].ewma_probability, 81.25);
  EXPECT_EQ(r.max_tp_rate, 7);
  EXPECT_EQ(r.max_prob_rate, 7);
}

TEST(MinstrelHtTest, RetryChainGoesBestSecondThenProbability) {
  MinstrelHt minstrel(PhyHt20(), MediumConfig::Minstrel{}, 1);
  MinstrelHtRemote r = minstrel.NewRemote(0);
  for (MinstrelHtRateStats& rate : r.rates) rate.attempts = 0;
  // Set the chain by hand: best MCS 7 (3 tries), second MCS 5 (2), probability MCS 2 (4).
  r.max_tp_rate = 7;
  r.max_tp_rate2 = 5;
  r.max_prob_rate = 2;
  r.rates[7].retry_count = 3;
  r.rates[5].retry_count = 2;
  r.rates[2].retry_count = 4;
  r.tx_rate = 7;
  EXPECT_EQ(minstrel.CountRetries(r), 9u);
  std::vector<int> chain = {r.tx_rate};
  while (minstrel.NeedRetransmission(r)) {
    minstrel.ReportDataFailed(r);
    if (minstrel.NeedRetransmission(r)) chain.push_back(r.tx_rate);
  }
  // Tries 1-3 at MCS 7 (long retry < 3), 4-5 at MCS 5 (< 3 + 2), 6-9 at MCS 2 (<= 9).
  EXPECT_EQ(chain, (std::vector<int>{7, 7, 7, 5, 5, 2, 2, 2, 2}));
  // Each failure counts at its rate, the ninth too (its long retry, 8, is below 9).
  EXPECT_EQ(r.rates[7].attempts, 3u);
  EXPECT_EQ(r.rates[2].attempts, 4u);
  // Sampling: the sample once, then ns-3 goes to the second best (not the best).
  r.long_retry = 0;
  r.is_sampling = true;
  r.tx_rate = 3;
  EXPECT_EQ(minstrel.CountRetries(r), 1u + 2u + 4u);
  minstrel.ReportDataFailed(r);
  EXPECT_EQ(r.tx_rate, 5);
  minstrel.ReportDataFailed(r);
  minstrel.ReportDataFailed(r);
  EXPECT_EQ(r.tx_rate, 2);
}

TEST(MinstrelHtTest, AmpduReportsCountMpdusAndFeedTheAverageLength) {
  MinstrelHt minstrel(PhyHt20(), MediumConfig::Minstrel{}, 1);
  MinstrelHtRemote r = minstrel.NewRemote(0);
  r.tx_rate = 4;
  // DoReportAmpduTxStatus: 18 of 20 MPDUs acknowledged count at the current rate.
  minstrel.ReportAmpduTxStatus(r, 18, 2, 10 * kNsPerMs);
  EXPECT_EQ(r.rates[4].successes, 18u);
  EXPECT_EQ(r.rates[4].attempts, 20u);
  EXPECT_EQ(r.total_packets, 20u);
  // A BlockAck with none acknowledged (or none at all) moves the retry chain instead.
  r.tx_rate = 4;
  minstrel.ReportAmpduTxStatus(r, 0, 20, 20 * kNsPerMs);
  EXPECT_EQ(r.long_retry, 1u);
  // UpdateStats: the average A-MPDU length, 40 MPDUs / 2 A-MPDUs = 20, weighted as the EWMA in
  // integers: (20 x 25 + 1 x 75) / 100 = 5. The next sample waits 16 + 2 x 5 frames.
  minstrel.UpdateStats(r, 50 * kNsPerMs);
  EXPECT_EQ(r.avg_ampdu_len, 5u);
  EXPECT_EQ(r.ampdu_len, 0u);
  r.sample_wait = r.sample_tries = 0;
  r.sample_count = 1;
  minstrel.ReportAmpduTxStatus(r, 5, 0, 60 * kNsPerMs);
  EXPECT_EQ(r.sample_wait, 16u + 2u * 5u - 1u);  // Set, then one frame of it waited (FindRate).
}

TEST(MinstrelHtTest, SampleTableDrawsFromTheSeedAndGroupsTakeTurns) {
  MediumConfig::Minstrel config;
  MinstrelHt a(PhyHt20(true), config, 7), b(PhyHt20(true), config, 7), c(PhyHt20(true), config, 8);
  const MinstrelHtRemote ra = a.NewRemote(0), rb = b.NewRemote(0), rc = c.NewRemote(0);
  ASSERT_EQ(ra.sample_table.size(), 8u);  // Rate ids of a group.
  ASSERT_EQ(ra.sample_table.front().size(), 10u);
  EXPECT_EQ(ra.sample_table, rb.sample_table);
  EXPECT_NE(ra.sample_table, rc.sample_table);
  for (const auto& row : ra.sample_table) {
    for (int rate : row) EXPECT_TRUE(rate >= 0 && rate < 8);
  }
  // RateInit's SetNextSample moves from group 0 to the next supported one (group 1, 2
  // streams) and one row down there; the walk then alternates the two groups.
  EXPECT_EQ(ra.sample_group, 1);
  EXPECT_EQ(ra.groups[1].index, 1);
  EXPECT_EQ(ra.groups[0].index, 0);
  // Two supported groups of 8 rates: 16 samples per group and update (8 per group), and the
  // first wait is none: 4 tries at once.
  EXPECT_EQ(ra.sample_count, 16u);
  EXPECT_EQ(ra.sample_tries, 4u);
}

// MCS of the DATA frames of a saturated 802.11n 5 GHz 20 MHz link over `duration_ns`.
std::vector<int> MinstrelHtMcs(double distance_m, uint64_t seed, TimeNs duration_ns) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.rate_control = MediumConfig::RateControl::kMinstrel;
  config.seed = seed;
  std::vector<int> mcs;
  for (const TxRecord& tx : LinkDataFrames(config, distance_m, 200 * kNsPerUs, duration_ns)) {
    mcs.push_back(tx.mcs);
  }
  return mcs;
}

TEST(MinstrelHtTest, OnAMediumLearnsTheLinkAndRepeatsItsChoicesForASeed) {
  // 5 m: every MCS gets through. It starts at the lowest index (MCS 0) and samples the faster
  // rates once each; the first update (50 ms) ranks them, later ones move it to MCS 7. Then
  // no sample is taken: the only rate faster than the second best is the best itself.
  const std::vector<int> near = MinstrelHtMcs(5, 1, 400 * kNsPerMs);
  ASSERT_GT(near.size(), 800u);
  EXPECT_EQ(near.front(), 0);
  const auto late = near.end() - 500;
  EXPECT_EQ(std::count(late, near.end(), 7), 500);
  EXPECT_EQ(near, MinstrelHtMcs(5, 1, 400 * kNsPerMs));
  EXPECT_NE(near, MinstrelHtMcs(5, 2, 400 * kNsPerMs));
  // 50 m: SNR about 12 dB, MCS 7 never gets through; the link settles lower.
  const std::vector<int> far = MinstrelHtMcs(50, 1, 400 * kNsPerMs);
  ASSERT_GT(far.size(), 100u);
  const auto far_late = far.end() - 100;
  EXPECT_LT(std::count(far_late, far.end(), 7), 20);
}

// The (streams, GI, width) groups DATA frames went in over a saturated 5 m link.
std::set<std::tuple<bool, int, bool, int>> GroupsSent(Standard standard, int width_mhz,
                                                        bool short_gi, int streams) {
  MediumConfig config;
  config.standard = standard;
  config.rate_control = MediumConfig::RateControl::kMinstrel;
  config.channel_width_mhz = width_mhz;
  config.short_guard_interval = short_gi;
  config.spatial_streams = streams;
  if (standard != Standard::k80211ac) config.mcs = 8 * streams - 1;  // HT: streams from it.
  std::set<std::tuple<bool, int, bool, int>> groups;
  for (const TxRecord& tx : LinkDataFrames(config, 5, 100 * kNsPerUs, 300 * kNsPerMs)) {
    groups.insert({tx.vht, tx.spatial_streams, tx.short_guard_interval, tx.channel_width_mhz});
    // VHT MCS 9 has no 20 MHz mode for 1 or 2 streams (ns-3's IsValidMcs): never chosen.
    EXPECT_FALSE(tx.vht && tx.mcs == 9 && tx.channel_width_mhz == 20);
  }
  return groups;
}

TEST(MinstrelHtTest, SamplesEveryGroupTheStationSupports) {
  using G = std::tuple<bool, int, bool, int>;  // VHT, streams, short GI, width.
  // 802.11n at 40 MHz, short GI supported, one stream: four HT groups.
  EXPECT_EQ(GroupsSent(Standard::k80211n5GHz, 40, true, 1),
            (std::set<G>{{false, 1, false, 20}, {false, 1, true, 20}, {false, 1, false, 40},
                         {false, 1, true, 40}}));
  // Two streams, long GI only, 20 MHz: the 1- and 2-stream groups.
  EXPECT_EQ(GroupsSent(Standard::k80211n2_4GHz, 20, false, 2),
            (std::set<G>{{false, 1, false, 20}, {false, 2, false, 20}}));
  // 802.11ac at 80 MHz, long GI: VHT groups only (UseLatestAmendmentOnly), 20 to 80 MHz.
  EXPECT_EQ(GroupsSent(Standard::k80211ac, 80, false, 1),
            (std::set<G>{{true, 1, false, 20}, {true, 1, false, 40}, {true, 1, false, 80}}));
}

TEST(MinstrelHtTest, AFrameNobodyAnswersGoesThreeTimes) {
  // Before any statistics every retry count is 1 (EWMA below 1 %), so ns-3's CountRetries is
  // 1 + 1 + 1; each failure raises the long retry count (UpdateRate), and the third ends the
  // chain (DoNeedRetransmission): 3 transmissions, all at MCS 0 (the lowest index).
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.rate_control = MediumConfig::RateControl::kMinstrel;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {1000, 0, 0});
  medium.EnableTrace(true);
  medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 500), 0);
  medium.AdvanceTo(kNsPerS, nullptr);
  const std::vector<TxRecord> txs = DrainTransmissions(medium);
  std::vector<int> mcs;
  for (const TxRecord& tx : txs) {
    if (tx.kind == FrameKind::kData) mcs.push_back(tx.mcs);
  }
  EXPECT_EQ(mcs, (std::vector<int>{0, 0, 0}));
}

}  // namespace
}  // namespace sitlnet::mac

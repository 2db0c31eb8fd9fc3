// EDCA (IEEE 802.11-2016 10.22.2; ns-3 3.37's QosTxop, ChannelAccessManager and
// QosFrameExchangeManager): the user priority of a frame, its access category, the default
// parameters, AIFS per category, internal collisions and TXOP bursts. Oracles: the standard's
// tables and arithmetic (AIFS = aSIFSTime + AIFSN x aSlotTime; a TXOP holds frames that fit in
// its limit), timed from the trace's own PPDU durations.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/mpdu.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::MakeEthernetFrame;

constexpr TimeNs kSifsNs = 16 * kNsPerUs, kSlotNs = 9 * kNsPerUs;  // OFDM, 17.4.4.

// An IPv4 frame from station `from` to `to` whose DS byte is `tos`.
std::vector<uint8_t> FrameWithTos(int from, int to, int payload_bytes, uint8_t tos) {
  std::vector<uint8_t> frame = MakeEthernetFrame(RobotMac(to), RobotMac(from), payload_bytes);
  frame[14] = 0x45;
  frame[15] = tos;
  return frame;
}

int Index(AccessCategory ac) { return static_cast<int>(ac); }

TEST(EdcaTest, UserPriorityIsTheDsBytesTopThreeBits) {
  EXPECT_EQ(UserPriorityOf(FrameWithTos(0, 1, 100, 0x00)), 0);
  EXPECT_EQ(UserPriorityOf(FrameWithTos(0, 1, 100, 0xc0)), 6);  // ping -Q 0xc0
  EXPECT_EQ(UserPriorityOf(FrameWithTos(0, 1, 100, 0xb8)), 5);  // DSCP EF (46): CS5's 5.
  EXPECT_EQ(UserPriorityOf(FrameWithTos(0, 1, 100, 0x20)), 1);  // CS1
  EXPECT_EQ(UserPriorityOf(FrameWithTos(0, 1, 100, 0xe0)), 7);
  std::vector<uint8_t> arp = FrameWithTos(0, 1, 100, 0xc0);
  arp[13] = 0x06;  // Ethertype 0x0806.
  EXPECT_EQ(UserPriorityOf(arp), 0);
  std::vector<uint8_t> ipv6 = MakeEthernetFrame(RobotMac(1), RobotMac(0), 100);
  ipv6[12] = 0x86;
  ipv6[13] = 0xdd;
  ipv6[14] = 0x6c;  // Version 6, traffic class 0xc0 across the nibbles.
  ipv6[15] = 0x00;
  EXPECT_EQ(UserPriorityOf(ipv6), 6);
  EXPECT_EQ(UserPriorityOf(std::vector<uint8_t>(14, 0)), 0);
}

TEST(EdcaTest, UserPriorityToAccessCategoryIsTable10_1) {
  const AccessCategory expected[8] = {
      AccessCategory::kBestEffort, AccessCategory::kBackground, AccessCategory::kBackground,
      AccessCategory::kBestEffort, AccessCategory::kVideo,      AccessCategory::kVideo,
      AccessCategory::kVoice,      AccessCategory::kVoice};
  for (int up = 0; up < 8; ++up) EXPECT_EQ(AccessCategoryOf(up), expected[up]) << up;
}

TEST(EdcaTest, DefaultParametersAreTable9_137AsNs3SetsThem) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  PhyInfo phy = DerivePhyInfo(config);
  EXPECT_TRUE(phy.qos);
  // aCWmin 15, aCWmax 1023: VO (aCWmin+1)/4-1 .. (aCWmin+1)/2-1, VI (aCWmin+1)/2-1 .. aCWmin.
  EXPECT_EQ(phy.edca[Index(AccessCategory::kVoice)], (EdcaParameters{2, 3, 7, 2080 * kNsPerUs}));
  EXPECT_EQ(phy.edca[Index(AccessCategory::kVideo)], (EdcaParameters{2, 7, 15, 4096 * kNsPerUs}));
  EXPECT_EQ(phy.edca[Index(AccessCategory::kBestEffort)], (EdcaParameters{3, 15, 1023, 0}));
  EXPECT_EQ(phy.edca[Index(AccessCategory::kBackground)], (EdcaParameters{7, 15, 1023, 0}));
  // 802.11b with QoS: aCWmin 31, the DSSS TXOP limits.
  config.standard = Standard::k80211b;
  config.rate_mbps = 11;
  config.qos = true;
  phy = DerivePhyInfo(config);
  EXPECT_EQ(phy.edca[Index(AccessCategory::kVoice)], (EdcaParameters{2, 7, 15, 3264 * kNsPerUs}));
  EXPECT_EQ(phy.edca[Index(AccessCategory::kVideo)], (EdcaParameters{2, 15, 31, 6016 * kNsPerUs}));
  EXPECT_EQ(phy.edca[Index(AccessCategory::kBestEffort)], (EdcaParameters{3, 31, 1023, 0}));
  // 802.11a without QoS: the DCF (AIFSN 2 = DIFS).
  phy = DerivePhyInfo(MediumConfig{});
  EXPECT_FALSE(phy.qos);
  EXPECT_EQ(phy.edca[Index(AccessCategory::kBestEffort)], (EdcaParameters{2, 15, 1023, 0}));
  EXPECT_EQ(phy.aifs_ns, phy.difs_ns);
}

// The first DATA frame of a station that queues one frame on an idle medium: it goes without a
// backoff, AIFS of its category after the frame arrived (10.3.4.2, 10.22.2.4).
TxRecord FirstData(const MediumConfig& config, uint8_t tos) {
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  medium.SubmitFrame(0, FrameWithTos(0, 1, 200, tos), 0);
  medium.AdvanceTo(10 * kNsPerMs, nullptr);
  for (const TxRecord& tx : DrainTransmissions(medium)) {
    if (tx.kind == FrameKind::kData) return tx;
  }
  ADD_FAILURE() << "no DATA frame";
  return {};
}

TEST(EdcaTest, DcfStationsIgnoreTheDsByteQosStationsUseIt) {
  MediumConfig config;  // 802.11a: the DCF unless qos.
  TxRecord tx = FirstData(config, 0xc0);
  EXPECT_FALSE(tx.qos);
  EXPECT_EQ(tx.start_ns, kSifsNs + 2 * kSlotNs);  // DIFS.
  EXPECT_EQ(MpduBytes(tx)[0], 0x08);              // Data, not QoS Data.
  config.qos = true;
  tx = FirstData(config, 0xc0);
  EXPECT_TRUE(tx.qos);
  EXPECT_EQ(tx.tid, 6);
  EXPECT_EQ(tx.start_ns, kSifsNs + 2 * kSlotNs);  // AIFS[VO], AIFSN 2.
  const std::vector<uint8_t> mpdu = MpduBytes(tx);
  EXPECT_EQ(mpdu[0], 0x88);  // QoS Data.
  EXPECT_EQ(mpdu[24], 6);    // QoS Control: TID 6, normal ACK.
  EXPECT_EQ(mpdu[25], 0);
  tx = FirstData(config, 0x00);
  EXPECT_EQ(tx.tid, 0);
  EXPECT_EQ(tx.start_ns, kSifsNs + 3 * kSlotNs);  // AIFS[BE], AIFSN 3.
  tx = FirstData(config, 0x20);
  EXPECT_EQ(tx.tid, 1);
  EXPECT_EQ(tx.start_ns, kSifsNs + 7 * kSlotNs);  // AIFS[BK], AIFSN 7.
}

TEST(EdcaTest, CfEndFrameLayout) {
  TxRecord tx;
  tx.kind = FrameKind::kCfEnd;
  tx.receiver = MacAddress{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  tx.transmitter = RobotMac(0);
  const std::vector<uint8_t> mpdu = MpduBytes(tx);
  ASSERT_EQ(mpdu.size(), 20u);  // 9.3.1.9: FC, Duration, RA, BSSID, FCS.
  EXPECT_EQ(mpdu[0], 0xE4);     // Control, subtype 14.
  EXPECT_EQ(mpdu[2], 0);
  EXPECT_EQ(mpdu[3], 0);
  for (int i = 4; i < 10; ++i) EXPECT_EQ(mpdu[i], 0xff);
}

// What one 802.11n MCS 7 station sends of `frames` 1500-byte frames with DS byte `tos`, queued
// at 0 for another station, in 100 ms.
struct OneSender {
  std::vector<TxRecord> air;
  size_t delivered = 0;
  StationCounters counters;
};
OneSender SendFromOneStation(int frames, uint8_t tos) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.aggregation = false;  // One MPDU per PPDU, as the ns-3 EDCA cells (every *_MaxAmpduSize 0).
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  for (int i = 0; i < frames; ++i) medium.SubmitFrame(0, FrameWithTos(0, 1, 1500, tos), 0);
  std::vector<Delivery> delivered;
  medium.AdvanceTo(100 * kNsPerMs, &delivered);
  return {DrainTransmissions(medium), delivered.size(), medium.counters(0)};
}

// 40 voice frames: TXOPs of 2.080 ms.
TEST(EdcaTest, VoiceTxopHoldsFramesSifsApartWhileTheyFitThenSendsCfEnd) {
  const OneSender sender = SendFromOneStation(40, 0xc0);
  EXPECT_EQ(sender.delivered, 40u);
  const std::vector<TxRecord>& air = sender.air;
  const TimeNs limit_ns = 2080 * kNsPerUs;
  const TimeNs cf_end_ns = PpduDurationNs(Standard::k80211a, 6, 20);  // Non-unicast rate.
  size_t i = 0;
  int txops = 0, cf_ends = 0, sent = 0;
  while (i < air.size()) {
    ASSERT_EQ(air[i].kind, FrameKind::kData) << i;
    const TimeNs txop_start = air[i].start_ns;
    ++txops;
    int frames = 0;
    while (true) {
      const TxRecord& data = air[i];
      ASSERT_EQ(data.kind, FrameKind::kData);
      ASSERT_LT(i + 1, air.size()) << "a DATA frame with no ACK after it";
      ASSERT_EQ(air[i + 1].kind, FrameKind::kAck);
      const TxRecord& ack = air[i + 1];
      ++frames;
      ++sent;
      const TimeNs data_ns = data.end_ns - data.start_ns;
      const TimeNs exchange_ns = data_ns + kSifsNs + (ack.end_ns - ack.start_ns);
      // Duration: the rest of the TXOP after this PPDU, rounded up to us (9.2.5.2), at least
      // SIFS + ACK; the ACK's is the DATA's less SIFS + ACK (9.2.5.7).
      const TimeNs rest_ns = std::max(txop_start + limit_ns - data.end_ns,
                                      kSifsNs + (ack.end_ns - ack.start_ns));
      EXPECT_EQ(data.duration_us, (rest_ns + kNsPerUs - 1) / kNsPerUs);
      EXPECT_EQ(ack.duration_us,
                data.duration_us - (kSifsNs + ack.end_ns - ack.start_ns) / kNsPerUs);
      i += 2;
      const TimeNs next_ns = ack.end_ns + kSifsNs;
      const TimeNs remaining_ns = txop_start + limit_ns - next_ns;
      if (i < air.size() && air[i].kind == FrameKind::kData && air[i].start_ns == next_ns) {
        EXPECT_LE(exchange_ns, remaining_ns);  // The next frame fits.
        continue;
      }
      if (i == air.size()) break;
      // The next frame does not fit, or there is none (the queue ran dry): ns-3 ends the TXOP
      // alike (StartFrameExchange fails, SendCfEndIfNeeded).
      if (sent < 40) {
        EXPECT_GT(exchange_ns, remaining_ns) << "a frame that fits was not sent";
      }
      if (remaining_ns > cf_end_ns) {
        ASSERT_EQ(air[i].kind, FrameKind::kCfEnd);
        EXPECT_EQ(air[i].start_ns, next_ns);
        ++cf_ends;
        ++i;
      }
      break;
    }
    EXPECT_GE(frames, 2);
    if (i < air.size()) {
      // The next TXOP waits AIFS[VO] after the medium's last frame at least.
      EXPECT_GE(air[i].start_ns, air[i - 1].end_ns + kSifsNs + 2 * kSlotNs);
    }
  }
  EXPECT_GE(txops, 3);
  EXPECT_GE(cf_ends, 1);
  EXPECT_EQ(sender.counters.cf_end_tx, static_cast<uint64_t>(cf_ends));
}

TEST(EdcaTest, BestEffortSendsOneFramePerAccess) {
  const std::vector<TxRecord> air = SendFromOneStation(20, 0x00).air;
  int data = 0;
  for (size_t i = 1; i < air.size(); ++i) {
    EXPECT_NE(air[i].kind, FrameKind::kCfEnd);
    if (air[i].kind != FrameKind::kData) continue;
    ++data;
    ASSERT_LT(i + 1, air.size()) << "a DATA frame with no ACK after it";
    EXPECT_GE(air[i].start_ns - air[i - 1].end_ns, kSifsNs + 3 * kSlotNs);
    EXPECT_EQ(air[i].duration_us, 16 + (air[i + 1].end_ns - air[i + 1].start_ns) / kNsPerUs);
  }
  EXPECT_EQ(data, 19);
}

// One station saturating voice and best effort, best effort's CW forced to 0: its backoff
// always ends AIFS[BE] = SIFS + 3 slots after the medium turns idle. Voice ends SIFS + 2 + k
// slots after, k from its CW: before best effort (k = 0), with it (k = 1: an internal
// collision that voice wins), or after (best effort sends and voice freezes).
TEST(EdcaTest, InternalCollisionGoesToTheHigherCategory) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.aggregation = false;  // Frame by frame, as the ns-3 EDCA cells.
  config.cw_min = 0;  // Best effort's (the override's category).
  config.cw_max = 0;
  config.short_retry_limit = config.long_retry_limit = 1000000;
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {1, 0, 0});
  const std::vector<uint8_t> voice = FrameWithTos(0, 1, 1500, 0xc0);
  const std::vector<uint8_t> best_effort = FrameWithTos(0, 1, 1500, 0x00);
  int voice_accesses = 0, voice_at_be_aifs = 0, be_accesses = 0;
  TimeNs last_end_ns = 0;  // The medium is idle from the start.
  for (TimeNs t = 0; t < 500 * kNsPerMs; t += kNsPerMs) {
    for (int k = 0; k < 8; ++k) {
      medium.SubmitFrame(0, voice, t);
      medium.SubmitFrame(0, best_effort, t);
    }
    medium.AdvanceTo(t + kNsPerMs, nullptr);
    for (const TxRecord& tx : DrainTransmissions(medium)) {
      const TimeNs gap_ns = tx.start_ns - last_end_ns;
      last_end_ns = tx.end_ns;
      if (tx.kind != FrameKind::kData || gap_ns <= kSifsNs) continue;  // Within a TXOP.
      if (tx.tid == 6) {
        ++voice_accesses;
        EXPECT_TRUE(gap_ns == kSifsNs + 2 * kSlotNs || gap_ns == kSifsNs + 3 * kSlotNs) << gap_ns;
        if (gap_ns == kSifsNs + 3 * kSlotNs) ++voice_at_be_aifs;
      } else {
        ++be_accesses;
        EXPECT_EQ(gap_ns, kSifsNs + 3 * kSlotNs);
      }
    }
  }
  EXPECT_GT(voice_accesses, 100);
  EXPECT_GT(be_accesses, 100);
  EXPECT_GT(voice_at_be_aifs, 10);
  // Every voice access at best effort's instant met best effort's expired backoff.
  EXPECT_EQ(medium.counters(0).internal_collisions, static_cast<uint64_t>(voice_at_be_aifs));
}

// What issue 44 asks of a robot's `ping -Q 0xc0`: robot A pings B every 10 ms while B saturates
// the channel with best-effort frames for A. The echo reply waits in B's queue of its access
// category: at voice it has its own, at best effort it waits behind B's 500 frames. The p99 of
// the round trip (request queued at A to reply delivered at A) over 2 s.
TimeNs PingRttP99Ns(uint8_t tos) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  // Without A-MPDU. With ns-3's default (BE 65535 B) a best-effort PPDU at MCS 7 lasts up to
  // 5.4 ms, and one on the air delays the voice ping: its p99 was 9.4 ms (block_ack branch).
  config.aggregation = false;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {});
  medium.AddStation(RobotMac(1), {5, 0, 0});
  const std::vector<uint8_t> bulk = FrameWithTos(1, 0, 1500, 0x00);
  std::vector<TimeNs> rtts_ns;
  TimeNs sent_ns = -1;
  std::vector<Delivery> delivered;
  for (TimeNs t = 0; t < 2 * kNsPerS; t += 100 * kNsPerUs) {
    medium.SubmitFrame(1, bulk, t);  // 15 000 frames/s: more than MCS 7 carries.
    if (t % (10 * kNsPerMs) == 0) {
      medium.SubmitFrame(0, FrameWithTos(0, 1, 84, tos), t);  // Echo request.
      sent_ns = t;
    }
    medium.AdvanceTo(t + 100 * kNsPerUs, &delivered);
    for (const Delivery& d : delivered) {
      if (d.ethernet_frame.size() != 98) continue;
      if (d.station == 1) {
        medium.SubmitFrame(1, FrameWithTos(1, 0, 84, tos), d.delivery_ns);  // Echo reply.
      } else if (t > 500 * kNsPerMs) {
        rtts_ns.push_back(d.delivery_ns - sent_ns);
      }
    }
    delivered.clear();
  }
  if (rtts_ns.size() < 20) return 2 * kNsPerS;  // Most replies never came back.
  std::sort(rtts_ns.begin(), rtts_ns.end());
  return rtts_ns[rtts_ns.size() * 99 / 100];
}

TEST(EdcaTest, VoicePingStaysFastUnderBestEffortSaturationBestEffortPingDoesNot) {
  const TimeNs voice_ns = PingRttP99Ns(0xc0), best_effort_ns = PingRttP99Ns(0x00);
  RecordProperty("voice_rtt_p99_us", static_cast<int>(voice_ns / kNsPerUs));
  RecordProperty("best_effort_rtt_p99_us", static_cast<int>(best_effort_ns / kNsPerUs));
  EXPECT_LT(voice_ns, 5 * kNsPerMs);
  EXPECT_GT(best_effort_ns, 5 * kNsPerMs);
}

}  // namespace
}  // namespace sitlnet::mac

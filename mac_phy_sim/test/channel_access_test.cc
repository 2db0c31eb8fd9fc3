// DCF channel access in details the saturation matrix never reaches (queues
// there never run empty): a frame arriving at an idle station, an immediate
// access that the medium interrupts, and the 4 us a frame needs to make an
// idle station's medium busy. TCP between two robots (one saturated sender,
// one answering every other frame) depends on all three.
#include <gtest/gtest.h>

#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::MakeEthernetFrame;

constexpr TimeNs kDifsNs = 34 * kNsPerUs;  // 802.11a: SIFS 16 + 2 slots of 9.
constexpr TimeNs kSifsNs = 16 * kNsPerUs;

// Start of the first DATA transmission of `station` in the trace, -1 if none.
TimeNs FirstDataStart(const std::vector<TxRecord>& txs, StationId station) {
  for (const TxRecord& tx : txs) {
    if (tx.source == station && tx.kind == FrameKind::kData) return tx.start_ns;
  }
  return -1;
}

// ns-3's ChannelAccessManager::NeedBackoffUponAccess: an idle medium and a
// zero backoff give access DIFS after the frame is queued, even when the
// medium has been idle for much longer (not at once).
TEST(ChannelAccessTest, AFrameQueuedAtALongIdleStationWaitsDifsFromItsArrival) {
  Medium medium(MediumConfig{});
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {10, 0, 0});
  medium.EnableTrace(true);
  const TimeNs queued_ns = 50 * kNsPerMs;
  medium.SubmitFrame(a, MakeEthernetFrame(RobotMac(1), RobotMac(0), 1500), queued_ns);
  medium.AdvanceTo(60 * kNsPerMs, nullptr);
  EXPECT_EQ(FirstDataStart(DrainTransmissions(medium), a), queued_ns + kDifsNs);
}

// An immediate access that another station's frame interrupts draws a random
// backoff (10.3.4.2: the medium did not stay idle for DIFS), counted from DIFS
// after that exchange: whole slots, 0 to CWmin, and not 0 for every seed.
// ns-3 3.37 keeps the zero backoff here (docs/mac_phy_sim.md says why this
// model does not).
TEST(ChannelAccessTest, AnInterruptedImmediateAccessDrawsARandomBackoff) {
  constexpr TimeNs kSlotNs = 9 * kNsPerUs;
  int seeds_with_a_backoff = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    MediumConfig config;
    config.seed = seed;
    Medium medium(config);
    const StationId y = medium.AddStation(RobotMac(0), {0, 0, 0});
    const StationId x = medium.AddStation(RobotMac(1), {1, 0, 0});
    medium.AddStation(RobotMac(2), {2, 0, 0});
    medium.EnableTrace(true);
    // Y starts at DIFS (34 us); X's frame arrives at 10 us, its access
    // would be at 44 us: Y's frame interrupts it.
    medium.SubmitFrame(y, MakeEthernetFrame(RobotMac(2), RobotMac(0), 1500), 0);
    medium.SubmitFrame(x, MakeEthernetFrame(RobotMac(2), RobotMac(1), 100), 10 * kNsPerUs);
    medium.AdvanceTo(5 * kNsPerMs, nullptr);
    const std::vector<TxRecord> txs = DrainTransmissions(medium);
    TimeNs exchange_end_ns = -1;
    for (const TxRecord& tx : txs) {
      if (tx.kind == FrameKind::kAck) {
        exchange_end_ns = tx.end_ns;
        break;
      }
    }
    ASSERT_EQ(FirstDataStart(txs, y), kDifsNs) << seed;
    const TimeNs y_end_ns =
        kDifsNs + PpduDurationNs(Standard::k80211a, 54, MpduBytesForEthernet(1514));
    ASSERT_EQ(exchange_end_ns, y_end_ns + kSifsNs + PpduDurationNs(Standard::k80211a, 24, 14))
        << seed;
    // Propagation delay is off: X counts from the ACK's end, in whole slots.
    const TimeNs after_difs_ns = FirstDataStart(txs, x) - (exchange_end_ns + kDifsNs);
    ASSERT_GE(after_difs_ns, 0) << seed;
    EXPECT_EQ(after_difs_ns % kSlotNs, 0) << seed;
    const TimeNs slots = after_difs_ns / kSlotNs;
    EXPECT_LE(slots, 15) << seed;
    if (slots > 0) ++seeds_with_a_backoff;
    EXPECT_EQ(medium.counters(x).tx_failures, 0u) << seed;
  }
  EXPECT_GT(seeds_with_a_backoff, 0);
}

// ns-3 3.37 reports a frame's arrival at an idle station to channel access
// only when preamble detection ends, 4 us in (PhyEntity's
// EndPreambleDetectionPeriod); the OFDM PHY's aCCATime is the same 4 us. A
// station whose access falls inside those 4 us (or at their end) still sends,
// and the two frames collide; one whose access falls after them defers.
TEST(ChannelAccessTest, AFrameBecomesBusyForAnIdleStationOnlyAfterPreambleDetection) {
  // Y starts at 34 us; X's access is at x_queued_us + 34: 37, 38 (the end of
  // the 4 us) or 39 us.
  for (const int x_queued_us : {3, 4, 5}) {
    Medium medium(MediumConfig{});
    const StationId y = medium.AddStation(RobotMac(0), {0, 0, 0});
    const StationId x = medium.AddStation(RobotMac(1), {1, 0, 0});
    medium.AddStation(RobotMac(2), {2, 0, 0});
    medium.EnableTrace(true);
    medium.SubmitFrame(y, MakeEthernetFrame(RobotMac(2), RobotMac(0), 1500), 0);
    medium.SubmitFrame(x, MakeEthernetFrame(RobotMac(2), RobotMac(1), 1500),
                       x_queued_us * kNsPerUs);
    medium.AdvanceTo(kNsPerMs, nullptr);
    const std::vector<TxRecord> txs = DrainTransmissions(medium);
    ASSERT_EQ(FirstDataStart(txs, y), kDifsNs) << x_queued_us;
    const TimeNs x_start_ns = FirstDataStart(txs, x);
    if (x_queued_us <= 4) {
      EXPECT_EQ(x_start_ns, x_queued_us * kNsPerUs + kDifsNs) << x_queued_us;
      // At least the first attempt of each (their retries may meet again).
      EXPECT_GE(medium.counters(y).tx_failures, 1u) << x_queued_us;
      EXPECT_GE(medium.counters(x).tx_failures, 1u) << x_queued_us;
    } else {
      // After Y's exchange (DATA, SIFS, ACK at 24 Mb/s) and DIFS.
      const TimeNs exchange_end_ns =
          kDifsNs + PpduDurationNs(Standard::k80211a, 54, MpduBytesForEthernet(1514)) + kSifsNs +
          PpduDurationNs(Standard::k80211a, 24, 14);
      EXPECT_GE(x_start_ns, exchange_end_ns + kDifsNs);
      EXPECT_EQ(medium.counters(y).tx_failures, 0u);
      EXPECT_EQ(medium.counters(x).tx_failures, 0u);
    }
  }
}

// The medium can turn idle again inside those 4 us: here Z's frame, as strong
// as Y's at X and 2 us behind it, breaks X's preamble detection of Y, and the
// two together (-72 dBm) stay under CCA-ED (-62 dBm). ns-3 never reported the
// medium busy, so X sends at its access time, 37 us, not DIFS after the
// medium turned idle again.
TEST(ChannelAccessTest, AnAccessKeptInsideTheCcaDelayStandsWhenTheMediumTurnsIdleAgain) {
  Medium medium(MediumConfig{});
  const StationId x = medium.AddStation(RobotMac(0), {0, 0, 0});
  // 30 m from X: -75 dBm there; 60 m apart: -84 dBm, under each other's
  // preamble detection (-82 dBm) and CCA-ED.
  const StationId y = medium.AddStation(RobotMac(1), {-30, 0, 0});
  const StationId z = medium.AddStation(RobotMac(2), {30, 0, 0});
  medium.AddStation(RobotMac(3), {0, 2, 0});
  medium.EnableTrace(true);
  medium.SubmitFrame(y, MakeEthernetFrame(RobotMac(3), RobotMac(1), 1500), 0);  // On air at 34 us.
  medium.SubmitFrame(z, MakeEthernetFrame(RobotMac(3), RobotMac(2), 1500),
                     2 * kNsPerUs);  // At 36 us.
  medium.SubmitFrame(x, MakeEthernetFrame(RobotMac(3), RobotMac(0), 1500),
                     3 * kNsPerUs);  // Access at 37 us.
  medium.AdvanceTo(kNsPerMs, nullptr);
  const std::vector<TxRecord> txs = DrainTransmissions(medium);
  ASSERT_EQ(FirstDataStart(txs, y), kDifsNs);
  ASSERT_EQ(FirstDataStart(txs, z), 2 * kNsPerUs + kDifsNs);
  EXPECT_EQ(FirstDataStart(txs, x), 3 * kNsPerUs + kDifsNs);
}

}  // namespace
}  // namespace sitlnet::mac

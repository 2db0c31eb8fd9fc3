// The cause recorded for every station and frame (EnableCauses): each test
// builds the situation in the medium and checks the branch that decided.
// Geometry uses the 11a defaults: 16.02 dBm, loss 46.68 + 30 log10(d) dB,
// noise floor -93.97 dBm, preamble detection at -82 dBm and 4 dB.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::MakeEthernetFrame;

constexpr MacAddress kBroadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

double PathLossDb(double d_m) { return 46.6777 + 30 * std::log10(d_m); }

struct Traced {
  std::vector<TxRecord> txs;
  std::vector<DropRecord> drops;
  std::vector<Delivery> deliveries;
};

Traced RunTraced(Medium& medium, TimeNs until_ns) {
  Traced t;
  medium.AdvanceTo(until_ns, &t.deliveries);
  std::vector<TraceEvent> events;
  medium.DrainTrace(&events);
  for (TraceEvent& e : events) {
    if (e.tx) t.txs.push_back(std::move(*e.tx));
    if (e.drop) t.drops.push_back(*e.drop);
  }
  return t;
}

Medium Traced11a(MediumConfig config = {}) {
  Medium medium(config);
  medium.EnableTrace(true);
  medium.EnableCauses(true);
  return medium;
}

// The record of station `at` for the first DATA frame from `from`.
const RxRecord& At(const Traced& t, StationId from, StationId at) {
  for (const TxRecord& tx : t.txs) {
    if (tx.kind != FrameKind::kData || tx.source != from) continue;
    for (const RxRecord& r : tx.receptions) {
      if (r.station == at) return r;
    }
  }
  ADD_FAILURE() << "no DATA frame from " << from << " at " << at;
  static const RxRecord kNone;
  return kNone;
}

TEST(CausesTest, DecodedWithPathLossAndNoObstacle) {
  Medium medium = Traced11a();
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId b = medium.AddStation(RobotMac(1), {10, 0, 0});
  medium.SubmitFrame(a, MakeEthernetFrame(kBroadcast, RobotMac(0), 100), 0);
  const Traced t = RunTraced(medium, kNsPerMs);
  const RxRecord& r = At(t, a, b);
  EXPECT_EQ(r.cause, RxCause::kDecoded);
  EXPECT_EQ(r.outcome, RxOutcome::kReceived);
  EXPECT_NEAR(r.path_loss_db, PathLossDb(10), 1e-3);
  EXPECT_NEAR(r.obstacle_loss_db, 0, 1e-9);
  EXPECT_EQ(r.interferer, -1);
}

TEST(CausesTest, BelowThresholdBehindAnObstacleNamesItsShare) {
  // 20 m: -69.7 dBm in line of sight. A 10 m box across the path: 2 walls x 9
  // dB + 10 m x 0.4 dB = 22 dB (Sommer et al.), -91.7 dBm: above the noise
  // floor, under the -82 dBm preamble threshold.
  Medium medium = Traced11a();
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId b = medium.AddStation(RobotMac(1), {20, 0, 0});
  medium.AddObstacle({{10, 0, 0}, {10, 10, 10}, 0});
  medium.SubmitFrame(a, MakeEthernetFrame(kBroadcast, RobotMac(0), 100), 0);
  const Traced t = RunTraced(medium, kNsPerMs);
  const RxRecord& r = At(t, a, b);
  EXPECT_EQ(r.cause, RxCause::kBelowThreshold);
  EXPECT_NEAR(r.path_loss_db, PathLossDb(20), 1e-3);
  EXPECT_NEAR(r.obstacle_loss_db, 22, 1e-6);
  EXPECT_GT(r.rx_power_dbm, medium.phy().noise_floor_dbm);
  EXPECT_TRUE(t.deliveries.empty());
}

TEST(CausesTest, NoiseErrorWhenLockedButTooWeakForTheRate) {
  // 44 m: -79.9 dBm, SNR 14 dB: the preamble locks (>= -82 dBm, >= 4 dB) but
  // 54 Mb/s 64-QAM 3/4 needs about 20 dB: the error-rate draw loses it.
  MediumConfig config;
  config.short_retry_limit = 1;
  Medium medium = Traced11a(config);
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId b = medium.AddStation(RobotMac(1), {44, 0, 0});
  medium.SubmitFrame(a, MakeEthernetFrame(RobotMac(1), RobotMac(0), 1000), 0);
  const Traced t = RunTraced(medium, kNsPerMs);
  const RxRecord& r = At(t, a, b);
  EXPECT_EQ(r.cause, RxCause::kNoiseError);
  EXPECT_EQ(r.outcome, RxOutcome::kError);
  EXPECT_EQ(r.interferer, -1);
}

// Hidden pair around B: A at -30 m, C at +30 m (-75 dBm at B each), A and C
// 60 m apart (-84 dBm: under the preamble threshold, so neither defers).
struct HiddenPair {
  Medium medium = Traced11a();
  StationId b = medium.AddStation(RobotMac(0), {0, 0, 0});
  StationId a = medium.AddStation(RobotMac(1), {-30, 0, 0});
  StationId c = medium.AddStation(RobotMac(2), {30, 0, 0});
};

TEST(CausesTest, AlreadyReceivingAndCollisionNameEachOther) {
  // A's broadcast starts at DIFS (34 us), C's 50 us later: B is locked on A
  // (past its 4 us preamble detection) when C arrives; at equal power A's
  // SINR falls to 0 dB and A is lost too.
  HiddenPair p;
  p.medium.SubmitFrame(p.a, MakeEthernetFrame(kBroadcast, RobotMac(1), 100), 0);
  p.medium.SubmitFrame(p.c, MakeEthernetFrame(kBroadcast, RobotMac(2), 100), 50 * kNsPerUs);
  const Traced t = RunTraced(p.medium, kNsPerMs);
  const RxRecord& c_at_b = At(t, p.c, p.b);
  EXPECT_EQ(c_at_b.cause, RxCause::kAlreadyReceiving);
  EXPECT_EQ(c_at_b.interferer, p.a);
  const RxRecord& a_at_b = At(t, p.a, p.b);
  EXPECT_EQ(a_at_b.cause, RxCause::kCollision);
  EXPECT_EQ(a_at_b.interferer, p.c);
  // A was still on the air when C's frame reached it.
  const RxRecord& c_at_a = At(t, p.c, p.a);
  EXPECT_EQ(c_at_a.cause, RxCause::kOwnTransmission);
  EXPECT_EQ(c_at_a.outcome, RxOutcome::kTransmitting);
  // A's frame at C was under the preamble threshold (60 m), not a collision.
  EXPECT_EQ(At(t, p.a, p.c).cause, RxCause::kBelowThreshold);
  EXPECT_TRUE(t.deliveries.empty());
}

TEST(CausesTest, AWeakFrameAtABusyStationIsBelowThresholdNotAlreadyReceiving) {
  // As above, but C at 60 m from B (-84 dBm, under the -82 dBm preamble threshold): it would
  // not have been detected at an idle B either, so B being busy is not its cause.
  Medium medium = Traced11a();
  const StationId b = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId a = medium.AddStation(RobotMac(1), {-30, 0, 0});
  const StationId c = medium.AddStation(RobotMac(2), {60, 0, 0});
  medium.SubmitFrame(a, MakeEthernetFrame(kBroadcast, RobotMac(1), 100), 0);
  medium.SubmitFrame(c, MakeEthernetFrame(kBroadcast, RobotMac(2), 100), 50 * kNsPerUs);
  const Traced t = RunTraced(medium, kNsPerMs);
  const RxRecord& c_at_b = At(t, c, b);
  EXPECT_EQ(c_at_b.outcome, RxOutcome::kCollided);  // The model's outcome is unchanged.
  EXPECT_EQ(c_at_b.cause, RxCause::kBelowThreshold);
  EXPECT_EQ(c_at_b.interferer, -1);
}

TEST(CausesTest, SimultaneousStartsAreBothCollisions) {
  // Both start at 34 us at equal power: both preambles are missed (ns-3).
  HiddenPair p;
  p.medium.SubmitFrame(p.a, MakeEthernetFrame(kBroadcast, RobotMac(1), 100), 0);
  p.medium.SubmitFrame(p.c, MakeEthernetFrame(kBroadcast, RobotMac(2), 100), 0);
  const Traced t = RunTraced(p.medium, kNsPerMs);
  const RxRecord& a_at_b = At(t, p.a, p.b);
  const RxRecord& c_at_b = At(t, p.c, p.b);
  EXPECT_EQ(a_at_b.cause, RxCause::kCollision);
  EXPECT_EQ(a_at_b.interferer, p.c);
  EXPECT_EQ(c_at_b.cause, RxCause::kCollision);
  EXPECT_EQ(c_at_b.interferer, p.a);
}

TEST(CausesTest, RetryLimitIsRecordedAtTheSenderWithEachAttemptsCause) {
  Medium medium = Traced11a();
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId b = medium.AddStation(RobotMac(1), {60, 0, 0});  // -85 dBm: never locks.
  medium.SubmitFrame(a, MakeEthernetFrame(RobotMac(1), RobotMac(0), 100), 0);
  const Traced t = RunTraced(medium, 100 * kNsPerMs);
  ASSERT_EQ(t.drops.size(), 1u);
  EXPECT_EQ(t.drops[0].reason, DropReason::kRetryLimit);
  EXPECT_EQ(t.drops[0].station, a);
  int attempts = 0;
  for (const TxRecord& tx : t.txs) {
    ASSERT_EQ(tx.receptions.size(), 1u);
    EXPECT_EQ(tx.receptions[0].station, b);
    EXPECT_EQ(tx.receptions[0].cause, RxCause::kBelowThreshold);
    ++attempts;
  }
  EXPECT_EQ(attempts, 7);  // dot11ShortRetryLimit.
}

TEST(CausesTest, QueueFullAndQueueExpiryAreRecordedAtTheSender) {
  // As FrameExchangeTest.FramesOlderThanMaxDelayExpireOnInsertAndAtAccess: B
  // holds the medium 18.6 ms; A's queue of 3 fills, one arrival is refused,
  // then waiting frames expire.
  MediumConfig config;
  config.standard = Standard::k80211b;
  config.rate_mbps = 1;
  config.queue_limit_frames = 3;
  config.queue_max_delay_ns = 1 * kNsPerMs;
  Medium medium = Traced11a(config);
  const StationId a = medium.AddStation(RobotMac(0), {});
  const StationId b = medium.AddStation(RobotMac(1), {1, 0, 0});
  medium.SubmitFrame(b, MakeEthernetFrame(kBroadcast, RobotMac(1), 2290), 0);
  const auto frame = MakeEthernetFrame(RobotMac(1), RobotMac(0), 100);
  for (int i = 0; i < 3; ++i) medium.SubmitFrame(a, frame, 100 * kNsPerUs);
  medium.SubmitFrame(a, frame, 500 * kNsPerUs);
  medium.SubmitFrame(a, frame, 1200 * kNsPerUs);
  const Traced t = RunTraced(medium, 1300 * kNsPerUs);
  int full = 0, expired = 0;
  for (const DropRecord& d : t.drops) {
    EXPECT_EQ(d.station, a);
    full += d.reason == DropReason::kQueueFull;
    expired += d.reason == DropReason::kQueueExpired;
  }
  EXPECT_EQ(full, 1);
  EXPECT_EQ(expired, 2);
}

TEST(CausesTest, CapturedFrameIsACollisionWithTheCapturer) {
  // ReceptionTest's capture geometry (11b, 1 Mb/s, 5 dB margin): C at 45 m
  // starts at DIFS, A at -10 m (20 dB stronger at B) 10 us later and takes B.
  MediumConfig config;
  config.standard = Standard::k80211b;
  config.rate_mbps = 1;
  config.reference_loss_db = 46.6777;
  config.capture_margin_db = 5;
  config.short_retry_limit = 1;
  Medium medium = Traced11a(config);
  const StationId b = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId a = medium.AddStation(RobotMac(1), {-10, 0, 0});
  const StationId c = medium.AddStation(RobotMac(2), {45, 0, 0});
  medium.SubmitFrame(c, MakeEthernetFrame(RobotMac(0), RobotMac(2), 100), 0);
  medium.SubmitFrame(a, MakeEthernetFrame(RobotMac(0), RobotMac(1), 100), 10 * kNsPerUs);
  const Traced t = RunTraced(medium, 5 * kNsPerMs);
  const RxRecord& c_at_b = At(t, c, b);
  EXPECT_EQ(c_at_b.cause, RxCause::kCollision);
  EXPECT_EQ(c_at_b.interferer, a);
  EXPECT_EQ(At(t, a, b).cause, RxCause::kDecoded);
}

// A busy fleet among obstacles with unicast and broadcast traffic.
Traced BusyFleet(bool causes, bool fading) {
  MediumConfig config;
  config.rts_threshold_bytes = 600;
  config.nakagami_fading = fading;
  config.seed = 7;
  Medium medium(config);
  medium.EnableTrace(true);
  medium.EnableCauses(causes);
  constexpr int kStations = 8;
  for (int i = 0; i < kStations; ++i) {
    medium.AddStation(RobotMac(i), {15.0 * (i % 4), 25.0 * (i / 4), 2});
  }
  medium.AddObstacle({{22, 12, 5}, {4, 4, 10}, 30});
  for (int k = 0; k < 400; ++k) {
    const int from = (k * 5) % kStations;
    const MacAddress to = k % 3 == 0 ? kBroadcast : RobotMac((from + 1 + k % 5) % kStations);
    medium.SubmitFrame(from, MakeEthernetFrame(to, RobotMac(from), 200 + (k * 37) % 1200),
                       k * 150 * kNsPerUs);
  }
  return RunTraced(medium, 200 * kNsPerMs);
}

TEST(CausesTest, RecordingChangesNothingAndAgreesWithTheOutcome) {
  for (const bool fading : {false, true}) {
    const Traced off = BusyFleet(false, fading);
    const Traced on = BusyFleet(true, fading);
    EXPECT_EQ(off.deliveries, on.deliveries);
    ASSERT_EQ(off.txs.size(), on.txs.size());
    ASSERT_EQ(off.drops.size(), on.drops.size());
    int collisions = 0;
    for (size_t i = 0; i < on.txs.size(); ++i) {
      ASSERT_EQ(off.txs[i].start_ns, on.txs[i].start_ns);
      ASSERT_EQ(off.txs[i].receptions.size(), on.txs[i].receptions.size());
      for (size_t j = 0; j < on.txs[i].receptions.size(); ++j) {
        const RxRecord& x = off.txs[i].receptions[j];
        const RxRecord& y = on.txs[i].receptions[j];
        EXPECT_EQ(x.outcome, y.outcome);
        EXPECT_EQ(x.rx_power_dbm, y.rx_power_dbm);
        EXPECT_EQ(x.sinr_db, y.sinr_db);
        EXPECT_EQ(x.cause, RxCause::kUnknown);
        switch (y.cause) {
          case RxCause::kDecoded:
            EXPECT_EQ(y.outcome, RxOutcome::kReceived);
            break;
          case RxCause::kBelowThreshold:
            // kCollided: it reached a busy station, but was too weak to be detected alone.
            EXPECT_TRUE(y.outcome == RxOutcome::kBelowSensitivity ||
                        (y.outcome == RxOutcome::kCollided && (y.rx_power_dbm < -82 || y.sinr_db < 4)));
            break;
          case RxCause::kNoiseError:
            EXPECT_EQ(y.outcome, RxOutcome::kError);
            break;
          case RxCause::kCollision:
          case RxCause::kAlreadyReceiving:
            EXPECT_EQ(y.outcome, RxOutcome::kCollided);
            EXPECT_GE(y.interferer, 0);
            EXPECT_NE(y.interferer, y.station);
            ++collisions;
            break;
          case RxCause::kOwnTransmission:
            EXPECT_EQ(y.outcome, RxOutcome::kTransmitting);
            break;
          case RxCause::kUnknown:
            ADD_FAILURE() << "no cause recorded";
        }
        // The split is recorded wherever a frame's power reaches the noise floor (-93.97 dBm).
        if (!fading && y.rx_power_dbm >= -93.97) {
          EXPECT_NEAR(y.path_loss_db + y.obstacle_loss_db, -y.rx_power_dbm + 16.0206, 1e-3);
        }
      }
    }
    EXPECT_GT(collisions, 0);
  }
}

}  // namespace
}  // namespace sitlnet::mac

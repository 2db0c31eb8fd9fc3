// 3GPP TR 37.885 V2V (ns-3 3.37 ThreeGppV2vUrban/HighwayPropagationLossModel
// and channel condition models). Formula values are worked out by hand from
// TR 37.885 Table 6.2.1-1 and 6.2-1; the statistical tests compare sample
// statistics with the TR's distributions at 4.5 standard errors (a false
// failure about once in 150000 runs; the draws are seeded, so a run repeats).
#include "mac_phy_sim/three_gpp_v2v.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "mac_phy_sim/channel.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

constexpr double kFc = 5.9e9;  // ITS band, as TR 37.885's evaluations.

TEST(ThreeGppV2vTest, PathLossFormulas) {
  // At 100 m and 5.9 GHz: urban LOS 38.77 + 33.4 + 18.2 log10 5.9 = 86.1995 dB,
  // highway LOS 32.4 + 40 + 20 log10 5.9 = 87.8170 dB, NLOS 36.85 + 60 + 18.9 log10 5.9 = 111.4191.
  EXPECT_NEAR(V2vLosLossDb(V2vEnvironment::kUrban, 100, kFc), 86.1995, 1e-4);
  EXPECT_NEAR(V2vLosLossDb(V2vEnvironment::kHighway, 100, kFc), 87.8170, 1e-4);
  EXPECT_NEAR(V2vNlosLossDb(100, kFc), 111.4191, 1e-4);
}

TEST(ThreeGppV2vTest, LosProbabilityCurves) {
  EXPECT_EQ(V2vLosProbability(V2vEnvironment::kUrban, 0), 1);  // 1.05 capped at 1.
  EXPECT_NEAR(V2vLosProbability(V2vEnvironment::kUrban, 100), 1.05 * std::exp(-1.14), 1e-12);
  EXPECT_NEAR(V2vLosProbability(V2vEnvironment::kHighway, 300), 0.21013 * 0.9 - 0.6 + 1.0193,
              1e-9);
  // Beyond 475 m the highway line: 0.54 - 0.001 (d - 475), never below 0.
  EXPECT_NEAR(V2vLosProbability(V2vEnvironment::kHighway, 675), 0.34, 1e-12);
  EXPECT_EQ(V2vLosProbability(V2vEnvironment::kHighway, 2000), 0);
}

// The per-pair LOS distance threshold agrees with the probability curve it replaces: for
// uniforms across (0, 1), LOS (u <= p_LOS(d)) just inside the threshold and not just beyond.
TEST(ThreeGppV2vTest, LosUpToIsWhereTheProbabilityFallsBelowTheDraw) {
  for (const V2vEnvironment environment : {V2vEnvironment::kUrban, V2vEnvironment::kHighway}) {
    int checked = 0;
    for (int k = 1; k < 2000; ++k) {
      const double u = k / 2000.0;
      const double up_to_m = V2vLosUpToM(environment, u);
      const double margin_m = 1e-6 * std::max(1.0, up_to_m);
      if (up_to_m > margin_m) {
        EXPECT_LE(u, V2vLosProbability(environment, up_to_m - margin_m)) << u;
      }
      EXPECT_GT(u, V2vLosProbability(environment, up_to_m + margin_m)) << u;
      ++checked;
    }
    EXPECT_EQ(checked, 1999);
  }
  // Worked by hand: urban u = 0.5 at ln(2.1) / 0.0114 = 65.08 m; highway u = 0.34 at 675 m
  // (the line), u = 0.8 at the quadratic's smaller root 126.4 m, u = 0.542 at 475 m (the step).
  EXPECT_NEAR(V2vLosUpToM(V2vEnvironment::kUrban, 0.5), std::log(2.1) / 0.0114, 1e-9);
  EXPECT_NEAR(V2vLosUpToM(V2vEnvironment::kHighway, 0.34), 675, 1e-9);
  EXPECT_NEAR(V2vLosUpToM(V2vEnvironment::kHighway, 0.8),
              (0.002 - std::sqrt(4e-6 - 4 * 2.1013e-6 * 0.2193)) / (2 * 2.1013e-6), 1e-9);
  EXPECT_EQ(V2vLosUpToM(V2vEnvironment::kHighway, 0.542), 475);
}

TEST(ThreeGppV2vTest, BlockageMomentsByHeight) {
  // TR 37.885 6.2.1: no loss when both antennas are above the blocker.
  EXPECT_EQ(V2vBlockageMoments(50, 1.7, 2, 1.6).std_db, 0);
  EXPECT_EQ(V2vBlockageMoments(50, 1.5, 1.5, 1.6).mean_db, 9);  // Both below, 15 log10 50 < 41.
  EXPECT_EQ(V2vBlockageMoments(50, 1.5, 1.5, 1.6).std_db, 4.5);
  EXPECT_EQ(V2vBlockageMoments(50, 1.5, 2, 1.6).mean_db, 5);
  // At 1000 m: 15 log10 1000 - 41 = 4 dB more.
  EXPECT_NEAR(V2vBlockageMoments(1000, 1.5, 2, 1.6).mean_db, 9, 1e-12);
}

// One model per seed, each with one pair (0, 1): independent realisations.
ThreeGppV2vModel Model(V2vEnvironment environment, uint64_t seed, bool shadowing) {
  ThreeGppV2vParams params;
  params.environment = environment;
  params.frequency_hz = kFc;
  params.shadowing = shadowing;
  params.seed = seed;
  return ThreeGppV2vModel(params);
}

TEST(ThreeGppV2vTest, LosShareFollowsTheProbability) {
  constexpr int kPairs = 20000;
  for (const auto& [environment, distance_m] :
       std::vector<std::pair<V2vEnvironment, double>>{{V2vEnvironment::kUrban, 50},
                                                      {V2vEnvironment::kUrban, 150},
                                                      {V2vEnvironment::kHighway, 300},
                                                      {V2vEnvironment::kHighway, 600}}) {
    int los = 0;
    for (int k = 0; k < kPairs; ++k) {
      ThreeGppV2vModel model = Model(environment, 1000 + k, false);
      model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {distance_m, 0, 2}, false});
      los += model.condition(0, 1) == LinkCondition::kLos;
    }
    const double p = V2vLosProbability(environment, distance_m);
    const double standard_error = std::sqrt(p * (1 - p) / kPairs);
    EXPECT_NEAR(static_cast<double>(los) / kPairs, p, 4.5 * standard_error) << distance_m;
  }
}

TEST(ThreeGppV2vTest, BlockedIsNlosAndNlosvAboveCarsAddsNothing) {
  int nlosv = 0;
  for (int k = 0; k < 200; ++k) {
    ThreeGppV2vModel model = Model(V2vEnvironment::kUrban, k, false);
    // Antennas at 2 and 3 m (both above 1.6 m): NLOSv costs what LOS costs.
    EXPECT_NEAR(model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {100, 0, 3}, false}),
                V2vLosLossDb(V2vEnvironment::kUrban, std::hypot(100, 1), kFc), 1e-9);
    nlosv += model.condition(0, 1) == LinkCondition::kNlosv;
    EXPECT_NEAR(model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {100, 0, 4}, true}),
                V2vNlosLossDb(std::hypot(100, 2), kFc), 1e-9);
    EXPECT_EQ(model.condition(0, 1), LinkCondition::kNlos);
  }
  EXPECT_GT(nlosv, 0);  // p_LOS(100 m) = 0.336: most pairs are NLOSv.
}

TEST(ThreeGppV2vTest, BlockageLossHasTheTrMoments) {
  // Antennas at 1.5 m, below the 1.6 m cars: the loss beyond LOS is log-normal
  // with mean 9 dB and std 4.5 dB (so positive: max(0, .) changes nothing).
  constexpr double kDistanceM = 200;  // p_LOS = 0.107: nearly all NLOSv.
  std::vector<double> extra_db;
  for (int k = 0; k < 20000; ++k) {
    ThreeGppV2vModel model = Model(V2vEnvironment::kUrban, 5000 + k, false);
    const double loss = model.LossDb(PathLossLink{0, 1, {0, 0, 1.5}, {kDistanceM, 0, 1.5}, false});
    if (model.condition(0, 1) != LinkCondition::kNlosv) continue;
    extra_db.push_back(loss - V2vLosLossDb(V2vEnvironment::kUrban, kDistanceM, kFc));
  }
  double sum = 0, sum2 = 0;
  for (double x : extra_db) sum += x, sum2 += x * x;
  const double n = static_cast<double>(extra_db.size());
  const double mean = sum / n, std_db = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 9, 4.5 * 4.5 / std::sqrt(n));
  // The sample std's standard error for this skewed law: under 4.5 x 0.03 at n ~ 17800.
  EXPECT_NEAR(std_db, 4.5, 4.5 * 0.03 * 4.5 / 2);
}

// Sample correlation of the shadowing before and after the pair's relative
// position moves by `moved_m`, over many independent pairs; and the std of the
// first values.
void ExpectCorrelation(V2vEnvironment environment, bool blocked, double moved_m) {
  constexpr int kPairs = 20000;
  const LinkCondition condition = blocked ? LinkCondition::kNlos : LinkCondition::kLos;
  std::vector<double> before, after;
  for (int k = 0; k < kPairs; ++k) {
    ThreeGppV2vModel model = Model(environment, 90000 + k, true);
    // p_LOS = 1 up to 4.28 m (urban) and 9.75 m (highway): station 1 moves on
    // a circle of that radius around station 0, by a chord of moved_m.
    const double radius_m = environment == V2vEnvironment::kUrban ? 4.2 : 9.7;
    const double angle = 2 * std::asin(moved_m / (2 * radius_m));
    model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {radius_m, 0, 2}, blocked});
    ASSERT_EQ(model.condition(0, 1), condition);
    before.push_back(model.shadowing_db(0, 1));
    model.LossDb(PathLossLink{
        0, 1, {0, 0, 2}, {radius_m * std::cos(angle), radius_m * std::sin(angle), 2}, blocked});
    ASSERT_EQ(model.condition(0, 1), condition);
    after.push_back(model.shadowing_db(0, 1));
  }
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (int k = 0; k < kPairs; ++k) {
    sa += before[k], sb += after[k];
    saa += before[k] * before[k], sbb += after[k] * after[k], sab += before[k] * after[k];
  }
  const double n = kPairs;
  const double var_a = saa / n - (sa / n) * (sa / n), var_b = sbb / n - (sb / n) * (sb / n);
  const double r = (sab / n - sa / n * sb / n) / std::sqrt(var_a * var_b);
  const double expected = std::exp(-moved_m / V2vShadowingCorrelationM(condition));
  // The standard error of a sample correlation is about (1 - R^2) / sqrt(n).
  EXPECT_NEAR(r, expected, 4.5 * std::max(1 - expected * expected, 0.01) / std::sqrt(n))
      << moved_m;
  const double sigma = V2vShadowingStdDb(condition);
  // The std of a normal sample: standard error sigma / sqrt(2 n).
  EXPECT_NEAR(std::sqrt(var_a), sigma, 4.5 * sigma / std::sqrt(2 * n));
  EXPECT_NEAR(std::sqrt(var_b), sigma, 4.5 * sigma / std::sqrt(2 * n));
}

TEST(ThreeGppV2vTest, ShadowingAutocorrelationLos) {
  for (double moved_m : {1.0, 5.0}) ExpectCorrelation(V2vEnvironment::kUrban, false, moved_m);
  for (double moved_m : {2.0, 10.0, 19.0}) {
    ExpectCorrelation(V2vEnvironment::kHighway, false, moved_m);
  }
}

TEST(ThreeGppV2vTest, ShadowingAutocorrelationNlos) {
  for (double moved_m : {2.0, 8.0}) ExpectCorrelation(V2vEnvironment::kUrban, true, moved_m);
}

TEST(ThreeGppV2vTest, NoNewDrawWithoutMovement) {
  ThreeGppV2vModel model = Model(V2vEnvironment::kHighway, 3, true);
  const PathLossLink link{0, 1, {0, 0, 1.5}, {80, 0, 1.5}, false};
  const double first = model.LossDb(link);
  EXPECT_EQ(model.LossDb(link), first);
  EXPECT_EQ(model.LossDb(PathLossLink{1, 0, link.b_m, link.a_m, false}), first);  // Symmetric.
}

// ns-3's UpdatePeriod: a static pair keeps its condition (and shadowing) up to and including
// one period after the draw, and draws the condition anew at its first evaluation after that.
// A new condition brings a new shadowing draw; the same one keeps the value (nothing moved).
TEST(ThreeGppV2vTest, UpdatePeriodRedrawsTheConditionOfAStaticPair) {
  constexpr int kPairs = 20000;
  constexpr TimeNs kPeriodNs = 100 * kNsPerMs;
  constexpr double kDistanceM = 150;  // Urban p_LOS 0.189.
  int los_first = 0, los_both = 0, changed = 0;
  for (int k = 0; k < kPairs; ++k) {
    ThreeGppV2vParams params;
    params.frequency_hz = kFc;
    params.seed = 50000 + k;
    params.update_period_ns = kPeriodNs;
    ThreeGppV2vModel model(params);
    PathLossLink link{0, 1, {0, 0, 2}, {kDistanceM, 0, 2}, false, 7};
    const double first_db = model.LossDb(link);
    const LinkCondition first = model.condition(0, 1);
    ASSERT_EQ(model.RecomputeAfterNs(0, 1), 7 + kPeriodNs);
    link.now_ns = 7 + kPeriodNs;  // Not yet: ns-3 redraws only when more than a period passed.
    ASSERT_EQ(model.LossDb(link), first_db);
    link.now_ns = 8 + kPeriodNs;
    const double second_db = model.LossDb(link);
    const LinkCondition second = model.condition(0, 1);
    ASSERT_EQ(model.RecomputeAfterNs(0, 1), 8 + 2 * kPeriodNs);
    if (first == second) {
      ASSERT_EQ(second_db, first_db);  // At 2 m NLOSv adds nothing: the same loss.
    } else {
      ++changed;
    }
    los_first += first == LinkCondition::kLos;
    los_both += first == LinkCondition::kLos && second == LinkCondition::kLos;
  }
  // The two draws are independent: LOS twice with p^2, a change with 2 p (1 - p).
  const double p = V2vLosProbability(V2vEnvironment::kUrban, kDistanceM);
  auto expect_share = [&](int count, double probability) {
    EXPECT_NEAR(static_cast<double>(count) / kPairs, probability,
                4.5 * std::sqrt(probability * (1 - probability) / kPairs));
  };
  expect_share(los_first, p);
  expect_share(los_both, p * p);
  expect_share(changed, 2 * p * (1 - p));
  // Period 0 (the default): the condition never changes.
  ThreeGppV2vModel frozen = Model(V2vEnvironment::kUrban, 3, true);
  const PathLossLink at_0{0, 1, {0, 0, 2}, {kDistanceM, 0, 2}, false, 0};
  const double frozen_db = frozen.LossDb(at_0);
  EXPECT_EQ(frozen.RecomputeAfterNs(0, 1), kNeverNs);
  PathLossLink later = at_0;
  later.now_ns = 3600 * kNsPerS;
  EXPECT_EQ(frozen.LossDb(later), frozen_db);
}

// The channel recomputes a static pair once the clock passes the model's RecomputeAfterNs,
// both through LossDb and LossDbUntil, and not before.
TEST(ThreeGppV2vTest, ChannelRecomputesAStaticPairAfterTheUpdatePeriod) {
  constexpr int kChannels = 4000;
  constexpr TimeNs kPeriodNs = 50 * kNsPerMs;
  int changed = 0, changed_until = 0;
  for (int k = 0; k < kChannels; ++k) {
    TimeNs now_ns = 0;
    ThreeGppV2vParams params;
    params.frequency_hz = kFc;
    params.seed = 70000 + k;
    params.update_period_ns = kPeriodNs;
    RadioChannel channel(std::make_unique<ThreeGppV2vModel>(params), true, 9, 0.4);
    channel.set_clock(&now_ns);
    channel.AddStation({0, 0, 2});
    channel.AddStation({150, 0, 2});
    channel.AddStation({0, 150, 2});
    const double first_db = channel.LossDb(0, 1);
    const double first_until_db = channel.LossDbUntil(0, 2, 1000);
    now_ns = kPeriodNs;
    ASSERT_EQ(channel.LossDb(1, 0), first_db);
    ASSERT_EQ(channel.LossDbUntil(2, 0, 1000), first_until_db);
    now_ns = kPeriodNs + 1;
    changed += channel.LossDb(1, 0) != first_db;
    changed_until += channel.LossDbUntil(2, 0, 1000) != first_until_db;
  }
  const double p = V2vLosProbability(V2vEnvironment::kUrban, 150);
  const double p_change = 2 * p * (1 - p);
  const double tolerance = 4.5 * std::sqrt(p_change * (1 - p_change) / kChannels);
  EXPECT_NEAR(static_cast<double>(changed) / kChannels, p_change, tolerance);
  EXPECT_NEAR(static_cast<double>(changed_until) / kChannels, p_change, tolerance);
}

TEST(ThreeGppV2vTest, RecoversFromAPositionThatIsNotANumber) {
  ThreeGppV2vModel model = Model(V2vEnvironment::kUrban, 4, true);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {3, 0, 2}, false});
  EXPECT_TRUE(std::isnan(model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {nan, 0, 2}, false})));
  const double back = model.LossDb(PathLossLink{0, 1, {0, 0, 2}, {3, 1, 2}, false});
  EXPECT_TRUE(std::isfinite(back));
  EXPECT_NEAR(back, V2vLosLossDb(V2vEnvironment::kUrban, std::sqrt(10.0), kFc), 5 * 3.0);
}

TEST(ThreeGppV2vTest, ChannelTakesNlosFromTheBoxesAndNoSommerLoss) {
  ThreeGppV2vParams params;
  params.frequency_hz = kFc;
  params.shadowing = false;
  RadioChannel channel(std::make_unique<ThreeGppV2vModel>(params), true, 9, 0.4);
  const int a = channel.AddStation({0, 0, 2});
  const int b = channel.AddStation({100, 0, 2});
  const int c = channel.AddStation({0, 3, 2});
  channel.AddObstacle(Box{{50, 0, 5}, {10, 10, 10}, 0});
  EXPECT_NEAR(channel.LossDb(a, b), V2vNlosLossDb(100, kFc), 1e-9);  // Not + 26 dB of Sommer.
  EXPECT_NEAR(channel.LossDb(a, c), V2vLosLossDb(V2vEnvironment::kUrban, 3, kFc), 1e-9);
  // A box added later across a static pair makes it NLOS too.
  channel.AddObstacle(Box{{0, 1.5, 2}, {1, 1, 1}, 0});
  EXPECT_NEAR(channel.LossDb(a, c), V2vNlosLossDb(3, kFc), 1e-9);
  // With obstacles off the box blocks nothing.
  RadioChannel open(std::make_unique<ThreeGppV2vModel>(params), false, 9, 0.4);
  open.AddStation({0, 0, 2});
  open.AddStation({100, 0, 2});
  open.AddObstacle(Box{{50, 0, 5}, {10, 10, 10}, 0});
  const double loss = open.LossDb(0, 1);
  EXPECT_LT(loss, V2vNlosLossDb(100, kFc));
  EXPECT_GE(loss, V2vLosLossDb(V2vEnvironment::kUrban, 100, kFc) - 1e-9);
}

// A fleet moving under 3GPP urban: the same seed gives the same bytes and
// powers; another seed other powers.
std::vector<TraceEvent> MovingRun(MediumConfig::PathLoss model, uint64_t seed, int sources,
                                  bool fading = false) {
  MediumConfig config;
  config.seed = seed;
  config.nakagami_fading = fading;
  config.rate_mbps = 6;
  config.path_loss_model = model;
  Medium medium(config);
  for (int i = 0; i < 6; ++i) medium.AddStation(RobotMac(i), {4.0 * i, 1.0 * (i % 2), 2});
  medium.AddObstacle(Box{{10, 8, 5}, {4, 4, 10}, 0});
  medium.EnableTrace(true);
  for (int k = 0; k < 40; ++k) {
    for (int i = 0; i < sources; ++i) {
      medium.SubmitFrame(i, testing::MakeEthernetFrame(RobotMac((i + 1) % 6), RobotMac(i), 400),
                         k * kNsPerMs);
      medium.SetStationPosition(i, {4.0 * i + 0.3 * k, 1.0 * (i % 2) + 0.5 * k, 2}, k * kNsPerMs);
    }
  }
  medium.AdvanceTo(kNsPerS, nullptr);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  return trace;
}

class ThreeGppV2vMediumTest : public ::testing::TestWithParam<bool> {};

TEST_P(ThreeGppV2vMediumTest, SameSeedSameBytes) {
  const auto urban = MediumConfig::PathLoss::kThreeGppV2vUrban;
  const bool fading = GetParam();
  const std::vector<TraceEvent> a = MovingRun(urban, 3, 6, fading),
                                b = MovingRun(urban, 3, 6, fading),
                                c = MovingRun(urban, 4, 6, fading);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(a[i].tx && b[i].tx);
    EXPECT_EQ(a[i].tx->start_ns, b[i].tx->start_ns);
    EXPECT_EQ(MpduBytes(*a[i].tx), MpduBytes(*b[i].tx));
    for (size_t r = 0; r < a[i].tx->receptions.size(); ++r) {
      EXPECT_EQ(a[i].tx->receptions[r].rx_power_dbm, b[i].tx->receptions[r].rx_power_dbm);
      if (i < c.size() && c[i].tx && r < c[i].tx->receptions.size() &&
          c[i].tx->receptions[r].rx_power_dbm != a[i].tx->receptions[r].rx_power_dbm) {
        differs = true;
      }
    }
  }
  EXPECT_TRUE(differs);
}

// The medium hands its clock to the channel: with an update period a static link's received
// power changes over a run (a new condition brings new shadowing), without one it never does;
// the same seed gives the same powers.
std::vector<double> StaticLinkPowersDbm(TimeNs update_period_ns, uint64_t seed) {
  MediumConfig config;
  config.seed = seed;
  config.rate_mbps = 6;
  config.path_loss_model = MediumConfig::PathLoss::kThreeGppV2vUrban;
  config.v2v_update_period_ns = update_period_ns;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 2});
  medium.AddStation(RobotMac(1), {135, 0, 2});  // p_LOS 0.225: a change at 35 % of updates.
  medium.EnableTrace(true);
  for (int k = 0; k < 200; ++k) {
    medium.SubmitFrame(0, testing::MakeEthernetFrame(RobotMac(1), RobotMac(0), 100),
                       k * 5 * kNsPerMs);
  }
  medium.AdvanceTo(kNsPerS, nullptr);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  std::vector<double> powers_dbm;
  for (const TraceEvent& event : trace) {
    if (!event.tx || event.tx->source != 0 || event.tx->kind != FrameKind::kData) continue;
    for (const auto& reception : event.tx->receptions) powers_dbm.push_back(reception.rx_power_dbm);
  }
  return powers_dbm;
}

TEST(ThreeGppV2vMediumTest, UpdatePeriodChangesAStaticLinkOverTime) {
  const std::vector<double> frozen = StaticLinkPowersDbm(0, 5);
  ASSERT_GE(frozen.size(), 200u);
  for (double power_dbm : frozen) EXPECT_EQ(power_dbm, frozen.front());
  const std::vector<double> updated = StaticLinkPowersDbm(10 * kNsPerMs, 5);
  ASSERT_GE(updated.size(), 200u);
  int changes = 0;
  for (size_t i = 1; i < updated.size(); ++i) changes += updated[i] != updated[i - 1];
  // A frame every 5 ms, its ACK 0.2 ms later: the first transmission more than 10 ms after a
  // draw is an ACK 10.2 ms after it, so about 98 updates in 1 s; a change at 2 p (1 - p) =
  // 0.35 of them: mean 34, sd 4.7. The bounds are 4 sd away.
  EXPECT_GE(changes, 15);
  EXPECT_LE(changes, 53);
  EXPECT_EQ(StaticLinkPowersDbm(10 * kNsPerMs, 5), updated);
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutNakagami, ThreeGppV2vMediumTest, ::testing::Bool());

// The model draws from streams of its own: with one sender whose frames all
// get through either way, its backoff (the MAC's draws) is the same under
// log-distance and 3GPP.
TEST(ThreeGppV2vMacTest, LeavesTheMacDrawsAsTheyWere) {
  const std::vector<TraceEvent> log_distance =
      MovingRun(MediumConfig::PathLoss::kLogDistance, 5, 1);
  const std::vector<TraceEvent> v2v = MovingRun(MediumConfig::PathLoss::kThreeGppV2vUrban, 5, 1);
  ASSERT_EQ(log_distance.size(), v2v.size());
  ASSERT_EQ(log_distance.size(), 80u);  // 40 DATA, 40 ACK: no retry.
  for (size_t i = 0; i < v2v.size(); ++i) {
    EXPECT_EQ(log_distance[i].tx->start_ns, v2v[i].tx->start_ns);
  }
}

}  // namespace
}  // namespace sitlnet::mac

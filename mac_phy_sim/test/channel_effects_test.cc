// Optional channel effects against their definitions: constant-speed
// propagation delay (ns-3 ConstantSpeedPropagationDelayModel), Nakagami-m
// fading per frame (the Gamma distribution of ns-3's
// NakagamiPropagationLossModel), log-normal shadowing per link. The effect
// on throughput is compared with ns-3 in the side-by-side matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::MakeEthernetFrame;

constexpr MacAddress kBroadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

TEST(ChannelEffectsTest, PropagationDelayIsDistanceOverTheSpeedOfLight) {
  // 300 m at 299792458 m/s: 1000.69 ns -> 1001 ns each way. Exponent 2 keeps
  // the link decodable at 6 Mb/s (-80.2 dBm).
  for (const bool delay : {false, true}) {
    MediumConfig config;
    config.rate_mbps = 6;
    config.path_loss_exponent = 2;
    config.propagation_delay = delay;
    Medium medium(config);
    medium.AddStation(RobotMac(0), {0, 0, 0});
    medium.AddStation(RobotMac(1), {300, 0, 0});
    medium.EnableTrace(true);
    medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 500), 0);
    std::vector<Delivery> out;
    medium.AdvanceTo(10 * kNsPerMs, &out);
    ASSERT_EQ(out.size(), 1u);
    const TimeNs delay_ns = delay ? 1001 : 0;
    const TimeNs airtime = PpduDurationNs(Standard::k80211a, 6, MpduBytesForEthernet(514));
    EXPECT_EQ(out[0].delivery_ns, 34 * kNsPerUs + airtime + delay_ns);
    std::vector<TraceEvent> trace;
    medium.DrainTrace(&trace);
    ASSERT_EQ(trace.size(), 2u);
    // The receiver answers SIFS after the DATA ended where it is; the ACK
    // reaches the sender another delay later, well inside its timeout.
    EXPECT_EQ(trace[1].tx->kind, FrameKind::kAck);
    EXPECT_EQ(trace[1].tx->start_ns, out[0].delivery_ns + 16 * kNsPerUs);
    EXPECT_EQ(medium.counters(0).sent_ok, 1u);
    EXPECT_EQ(medium.counters(0).retries, 0u);
  }
}

// A station whose position is not a number, or one farther than light travels in a second
// (heard only by a radio allowed 230 dB of loss), hears nothing: with the propagation delay on,
// its signal's events used to land near int64's end (a signed overflow) or before now.
TEST(ChannelEffectsTest, AStationAtNoPositionOrBeyondALightSecondHearsNothing) {
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  enum class Fading { kNone, kNakagami, kJakes, kJakesFromSpeed };
  for (const Fading fading :
       {Fading::kNone, Fading::kNakagami, Fading::kJakes, Fading::kJakesFromSpeed}) {
    for (const Vec3d far : {Vec3d{kNan, 0, 0}, Vec3d{3e8, 0, 0}, Vec3d{2.7e18, 0, 0}}) {
      MediumConfig config;
      config.standard = Standard::k80211g;
      config.path_loss_exponent = 1;
      config.tx_power_dbm = 30;
      config.rx_sensitivity_dbm = -200;
      config.propagation_delay = true;
      config.nakagami_fading = fading == Fading::kNakagami;
      config.jakes_fading = fading == Fading::kJakes || fading == Fading::kJakesFromSpeed;
      config.jakes_doppler_from_speed = fading == Fading::kJakesFromSpeed;
      Medium medium(config);
      medium.AddStation(RobotMac(0), {0, 0, 0});
      medium.AddStation(RobotMac(1), {10, 0, 0});
      medium.AddStation(RobotMac(2), far);
      medium.AddStation(RobotMac(3), {20, 0, 0});
      medium.SetStationPosition(3, far, 1);  // Moved there: the Doppler from speed sees it.
      medium.SubmitFrame(0, MakeEthernetFrame(kBroadcast, RobotMac(0), 500), 0);
      std::vector<Delivery> out;
      medium.AdvanceTo(kNsPerS, &out);
      ASSERT_EQ(out.size(), 1u) << far.x << " fading kind " << static_cast<int>(fading);
      EXPECT_EQ(out[0].station, 1);
      EXPECT_EQ(medium.NextEventNs(), std::nullopt);
    }
  }
}

// Received power of `frames` broadcasts over a 10 m link, relative to the
// mean (linear gains).
std::vector<double> FadingGains(double m, int frames) {
  MediumConfig config;
  config.nakagami_fading = true;
  config.nakagami_m0 = config.nakagami_m1 = config.nakagami_m2 = m;
  config.group_rate_mbps = 54;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {10, 0, 0});
  const double mean_dbm = config.tx_power_dbm - medium.LossDb(0, 1);
  medium.EnableTrace(true);
  const auto frame = MakeEthernetFrame(kBroadcast, RobotMac(0), 100);
  std::vector<double> gains;
  std::vector<TraceEvent> trace;
  for (int i = 0; i < frames; ++i) {
    medium.SubmitFrame(0, frame, i * kNsPerMs);
    medium.AdvanceTo((i + 1) * kNsPerMs, nullptr);
  }
  medium.DrainTrace(&trace);
  for (const TraceEvent& e : trace) {
    if (e.tx) gains.push_back(std::pow(10.0, (e.tx->receptions[0].rx_power_dbm - mean_dbm) / 10));
  }
  return gains;
}

TEST(ChannelEffectsTest, NakagamiGainsFollowTheGammaDistribution) {
  // Gain ~ Gamma(m, 1/m): mean 1; P(gain < 0.1) = 1 - e^-0.1 = 0.0952 for
  // m = 1 (Rayleigh), 1 - e^-0.2 (1 + 0.2) = 0.0175 for m = 2 (Erlang CDF).
  // 20,000 frames: standard errors 0.0021 and 0.0009; tolerances 4 of them.
  const struct {
    double m, p_below_tenth, tolerance;
  } cases[] = {{1, 1 - std::exp(-0.1), 0.0085}, {2, 1 - std::exp(-0.2) * 1.2, 0.0037}};
  for (const auto& c : cases) {
    const std::vector<double> gains = FadingGains(c.m, 20000);
    ASSERT_EQ(gains.size(), 20000u);
    double sum = 0;
    int below = 0;
    for (double g : gains) {
      sum += g;
      below += g < 0.1;
    }
    // Var = 1/m: the mean's standard error is 0.0071 (m = 1), 0.005 (m = 2).
    EXPECT_NEAR(sum / gains.size(), 1.0, 0.03) << "m=" << c.m;
    EXPECT_NEAR(static_cast<double>(below) / gains.size(), c.p_below_tenth, c.tolerance)
        << "m=" << c.m;
  }
}

TEST(ChannelEffectsTest, DelayUnderHalfANanosecondChangesNothing) {
  // Stations 1 mm apart (3.3 ps): the delay rounds to 0 ns and the run is
  // the one without propagation delay, frame for frame (so the side-by-side
  // matrix can keep ns-3's default delay model on everywhere).
  std::vector<TraceEvent> traces[2];
  for (const bool delay : {false, true}) {
    MediumConfig config;
    config.propagation_delay = delay;
    Medium medium(config);
    for (int i = 0; i < 4; ++i) medium.AddStation(RobotMac(i), {0.001 * i, 0, 0});
    medium.EnableTrace(true);
    for (int i = 0; i < 4; ++i) {
      for (int k = 0; k < 20; ++k) {
        medium.SubmitFrame(i, MakeEthernetFrame(RobotMac((i + 1) % 4), RobotMac(i), 300), 0);
      }
    }
    medium.AdvanceTo(kNsPerS, nullptr);
    medium.DrainTrace(&traces[delay]);
  }
  ASSERT_EQ(traces[0].size(), traces[1].size());
  for (size_t i = 0; i < traces[0].size(); ++i) {
    ASSERT_EQ(traces[0][i].tx.has_value(), traces[1][i].tx.has_value());
    if (traces[0][i].tx) {
      EXPECT_EQ(traces[0][i].tx->start_ns, traces[1][i].tx->start_ns) << i;
    }
  }
}

TEST(ChannelEffectsTest, LognormalShadowingIsAFixedGaussianPerLink) {
  // 40 stations on a circle: 780 links. The extra loss per link has mean 0
  // (standard error 8 / sqrt(780) = 0.29 dB) and standard deviation 8 dB
  // (standard error about 0.2 dB); it is symmetric and does not change when
  // the stations move (a per-link draw, not per frame).
  MediumConfig config;
  config.lognormal_shadowing_sigma_db = 8;
  config.seed = 7;
  Medium medium(config);
  const int n = 40;
  std::vector<Vec3d> positions;
  for (int i = 0; i < n; ++i) {
    positions.push_back({20 * std::cos(2 * M_PI * i / n), 20 * std::sin(2 * M_PI * i / n), 0});
    medium.AddStation(RobotMac(i), positions.back());
  }
  auto extra_db = [&](int a, int b) {
    const double dx = positions[a].x - positions[b].x, dy = positions[a].y - positions[b].y;
    return medium.LossDb(a, b) - (46.6777 + 30 * std::log10(std::hypot(dx, dy)));
  };
  double sum = 0, sum2 = 0;
  int links = 0;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const double x = extra_db(a, b);
      EXPECT_DOUBLE_EQ(medium.LossDb(a, b), medium.LossDb(b, a));
      sum += x;
      sum2 += x * x;
      ++links;
    }
  }
  const double mean = sum / links;
  const double sd = std::sqrt(sum2 / links - mean * mean);
  EXPECT_NEAR(mean, 0, 1.2);
  EXPECT_NEAR(sd, 8, 0.8);
  const double before = extra_db(0, 1);
  positions[1].x += 5;
  medium.SetStationPosition(1, positions[1], 0);
  medium.AdvanceTo(0, nullptr);
  EXPECT_NEAR(extra_db(0, 1), before, 1e-9);
}

}  // namespace
}  // namespace sitlnet::mac

namespace sitlnet::mac {
namespace {

// The same seed gives the same bytes with every channel effect and Ideal
// rate control on; another seed does not.
std::vector<TraceEvent> EffectsRun(uint64_t seed) {
  MediumConfig config;
  config.seed = seed;
  config.propagation_delay = true;
  config.nakagami_fading = true;
  config.lognormal_shadowing_sigma_db = 6;
  config.rate_control = MediumConfig::RateControl::kIdeal;
  Medium medium(config);
  for (int i = 0; i < 6; ++i) medium.AddStation(RobotMac(i), {15.0 * i, 3.0 * (i % 2), 0});
  medium.EnableTrace(true);
  for (int k = 0; k < 40; ++k) {
    for (int i = 0; i < 6; ++i) {
      medium.SubmitFrame(i, testing::MakeEthernetFrame(RobotMac((i + 1) % 6), RobotMac(i), 400),
                         k * kNsPerMs);
    }
  }
  medium.AdvanceTo(kNsPerS, nullptr);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  return trace;
}

TEST(ChannelEffectsTest, SameSeedSameBytesWithEveryEffectOn) {
  const std::vector<TraceEvent> a = EffectsRun(3), b = EffectsRun(3), c = EffectsRun(4);
  ASSERT_EQ(a.size(), b.size());
  bool differs = a.size() != c.size();
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].tx.has_value(), b[i].tx.has_value());
    if (!a[i].tx) continue;
    EXPECT_EQ(a[i].tx->start_ns, b[i].tx->start_ns);
    EXPECT_EQ(MpduBytes(*a[i].tx), MpduBytes(*b[i].tx));
    EXPECT_EQ(a[i].tx->rate_mbps, b[i].tx->rate_mbps);
    for (size_t r = 0; r < a[i].tx->receptions.size(); ++r) {
      EXPECT_EQ(a[i].tx->receptions[r].rx_power_dbm, b[i].tx->receptions[r].rx_power_dbm);
    }
    if (!differs && (!c[i].tx || c[i].tx->start_ns != a[i].tx->start_ns)) differs = true;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace sitlnet::mac

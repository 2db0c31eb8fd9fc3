// Jakes fading in the medium: the MAC's draws stay as they were, the same seed gives the same
// trace, and losses come in runs as long as Rayleigh's average fade duration predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/fading_statistics.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::MakeEthernetFrame;

constexpr MacAddress kBroadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

// Three stations 1 m apart exchanging unicast frames at 6 Mb/s for 2 s, 57 dB above what the
// rate needs (a Jakes gain that deep has probability about 2e-6 per frame).
std::vector<Delivery> Exchange(const MediumConfig& config, std::vector<TraceEvent>* trace) {
  Medium medium(config);
  for (int i = 0; i < 3; ++i) medium.AddStation(RobotMac(i), {static_cast<double>(i), 0, 0});
  medium.EnableTrace(true);
  for (int k = 0; k < 400; ++k) {
    const int from = k % 3, to = (k + 1) % 3;
    medium.SubmitFrame(from, MakeEthernetFrame(RobotMac(to), RobotMac(from), 300),
                       k * 5 * kNsPerMs);
  }
  std::vector<Delivery> out;
  medium.AdvanceTo(2 * kNsPerS + 100 * kNsPerMs, &out);
  medium.DrainTrace(trace);
  return out;
}

TEST(JakesMediumTest, LeavesTheMacDrawsAsTheyWere) {
  MediumConfig config;
  config.rate_mbps = 6;
  config.seed = 5;
  std::vector<TraceEvent> off_trace, on_trace, again_trace;
  const std::vector<Delivery> off = Exchange(config, &off_trace);
  config.jakes_fading = true;
  const std::vector<Delivery> on = Exchange(config, &on_trace);
  const std::vector<Delivery> again = Exchange(config, &again_trace);
  ASSERT_EQ(off.size(), 400u);
  ASSERT_EQ(on.size(), off.size());
  int powers_differ = 0;
  for (size_t i = 0; i < off.size(); ++i) {
    // Same backoffs, hence the same times: only the received powers change.
    EXPECT_EQ(on[i].delivery_ns, off[i].delivery_ns);
    EXPECT_EQ(on[i].source, off[i].source);
    EXPECT_EQ(on[i].station, off[i].station);
    EXPECT_EQ(on[i].ethernet_frame, off[i].ethernet_frame);
    powers_differ += on[i].rx_power_dbm != off[i].rx_power_dbm;
  }
  EXPECT_EQ(powers_differ, 400);
  EXPECT_TRUE(again == on);  // The same seed: the same deliveries, powers included.
  ASSERT_EQ(again_trace.size(), on_trace.size());
  for (size_t i = 0; i < on_trace.size(); ++i) {
    ASSERT_EQ(again_trace[i].tx.has_value(), on_trace[i].tx.has_value());
    if (!on_trace[i].tx) continue;
    for (size_t r = 0; r < on_trace[i].tx->receptions.size(); ++r) {
      EXPECT_EQ(again_trace[i].tx->receptions[r].rx_power_dbm,
                on_trace[i].tx->receptions[r].rx_power_dbm);
    }
  }
  config.seed = 6;
  std::vector<TraceEvent> other_trace;
  const std::vector<Delivery> other = Exchange(config, &other_trace);
  ASSERT_EQ(other.size(), on.size());
  EXPECT_NE(other[0].rx_power_dbm, on[0].rx_power_dbm);
}

// Frames lost under a sensitivity set at the link's mean power, and their runs.
struct LossRuns {
  long frames = 0, lost = 0, runs = 0;
  double mean_run_s = 0;  // From a run's first lost frame to the next frame received.
};

// One station broadcasts every 250 us for 20 s of virtual time to another 10 m away, with the
// RX sensitivity at the mean received power: a frame is lost exactly when the gain is under
// 0 dB (rho = 1), 34 dB over the noise otherwise. With `circle_speed_mps` > 0 the sender
// circles the receiver at 10 m (the mean power stays), its position updated every ms.
LossRuns RunLossRuns(MediumConfig config, double circle_speed_mps) {
  config.group_rate_mbps = 54;
  const double radius_m = 10;
  auto sender_at = [&](TimeNs t) {
    const double angle_rad = circle_speed_mps / radius_m * (t / 1e9);
    return Vec3d{radius_m * std::cos(angle_rad), radius_m * std::sin(angle_rad), 0};
  };
  {
    Medium probe(config);
    probe.AddStation(RobotMac(0), sender_at(0));
    probe.AddStation(RobotMac(1), {0, 0, 0});
    config.rx_sensitivity_dbm = config.tx_power_dbm - probe.LossDb(0, 1);  // -60.5 dBm.
  }
  Medium medium(config);
  medium.AddStation(RobotMac(0), sender_at(0));
  medium.AddStation(RobotMac(1), {0, 0, 0});
  medium.EnableTrace(true);
  const auto frame = MakeEthernetFrame(kBroadcast, RobotMac(0), 100);
  const TimeNs period_ns = 250 * kNsPerUs, chunk_ns = 100 * kNsPerMs;
  LossRuns result;
  TimeNs run_start_ns = -1, lost_ns = 0;
  std::vector<TraceEvent> trace;
  for (TimeNs t = 0; t < 20 * kNsPerS; t += chunk_ns) {
    for (TimeNs at = t; at < t + chunk_ns; at += period_ns) medium.SubmitFrame(0, frame, at);
    if (circle_speed_mps > 0) {
      for (TimeNs at = t + kNsPerMs; at <= t + chunk_ns; at += kNsPerMs) {
        medium.SetStationPosition(0, sender_at(at), at);
      }
    }
    medium.AdvanceTo(t + chunk_ns, nullptr);
    trace.clear();
    medium.DrainTrace(&trace);
    for (const TraceEvent& e : trace) {
      if (!e.tx) continue;
      const bool below = e.tx->receptions[0].outcome == RxOutcome::kBelowSensitivity;
      EXPECT_TRUE(below || e.tx->receptions[0].outcome == RxOutcome::kReceived);
      ++result.frames;
      result.lost += below;
      if (below && run_start_ns < 0) {
        run_start_ns = e.tx->start_ns;
        ++result.runs;
      } else if (!below && run_start_ns >= 0) {
        lost_ns += e.tx->start_ns - run_start_ns;
        run_start_ns = -1;
      }
    }
  }
  result.mean_run_s = lost_ns / 1e9 / result.runs;
  return result;
}

// About 1,500 fades of 8.6 ms on average (Rayleigh's closed form at 80 Hz); fade lengths
// spread about as much as their mean, so the mean of 1,500 is good to about 3 %, and the
// 0.25 ms sampling adds little. Rule: 10 %. The share of frames lost is a time average over
// the same fades: 1 - 1/e within 0.03.
TEST(JakesMediumTest, LossRunsLastTheAverageFadeDuration) {
  MediumConfig config;
  config.jakes_fading = true;
  const LossRuns r = RunLossRuns(config, 0);
  ASSERT_GT(r.frames, 70000);
  const double expected_s = RayleighMeanFadeS(config.jakes_doppler_hz, 1.0);
  EXPECT_NEAR(r.mean_run_s / expected_s, 1, 0.10);
  // A Rayleigh power gain is under its mean with probability 1 - 1/e.
  EXPECT_NEAR(static_cast<double>(r.lost) / r.frames, 1 - std::exp(-1.0), 0.03);
  std::printf("%ld frames, %.4f lost (1 - 1/e = %.4f), %ld fades of %.3f ms (closed form %.3f)\n",
              r.frames, static_cast<double>(r.lost) / r.frames, 1 - std::exp(-1.0), r.runs,
              r.mean_run_s * 1e3, expected_s * 1e3);
}

// With the Doppler from speed, a sender circling at 80 Hz x the wavelength (4.63 m/s at 5.18
// GHz) fades as a fixed 80 Hz process does; one at half the speed fades twice as long (the
// fade duration scales as 1 / f_d). Same rules as above; at 40 Hz half as many fades (about
// 780) make the mean good to about 4 %.
TEST(JakesMediumTest, DopplerFromSpeedSetsTheFadeDuration) {
  MediumConfig config;
  config.jakes_fading = true;
  config.jakes_doppler_from_speed = true;
  config.jakes_doppler_hz = 1;  // Unused with the Doppler from speed.
  const double wavelength_m = 299792458.0 / 5.18e9;
  for (const double doppler_hz : {80.0, 40.0}) {
    const LossRuns r = RunLossRuns(config, doppler_hz * wavelength_m);
    const double expected_s = RayleighMeanFadeS(doppler_hz, 1.0);
    EXPECT_NEAR(r.mean_run_s / expected_s, 1, 0.10) << doppler_hz << " Hz";
    EXPECT_NEAR(static_cast<double>(r.lost) / r.frames, 1 - std::exp(-1.0), 0.04);
    std::printf("%g Hz from speed: %ld fades of %.3f ms (closed form %.3f), %.4f lost\n",
                doppler_hz, r.runs, r.mean_run_s * 1e3, expected_s * 1e3,
                static_cast<double>(r.lost) / r.frames);
  }
  // A still pair keeps its gain: no Doppler, no fading in time.
  const LossRuns still = RunLossRuns(config, 0);
  EXPECT_TRUE(still.lost == 0 || still.lost == still.frames);
  EXPECT_LE(still.runs, 1);
}

}  // namespace
}  // namespace sitlnet::mac

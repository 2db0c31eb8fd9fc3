// Per-station tx power and rate, and Ideal rate control (ns-3 3.37's
// IdealWifiManager). Ideal is compared with ns-3 on a distance sweep in the
// side-by-side matrix; here: its rule and its starting point.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::MakeEthernetFrame;

TEST(RateControlTest, StationsHaveTheirOwnTxPowerAndRate) {
  Medium medium(MediumConfig{});  // 11a, 54 Mb/s, 16.0206 dBm by default.
  medium.AddStation(RobotMac(0), {0, 0, 0}, StationRadio{6.0, 12.0});
  medium.AddStation(RobotMac(1), {10, 0, 0});
  medium.EnableTrace(true);
  medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 500), 0);
  medium.SubmitFrame(1, MakeEthernetFrame(RobotMac(0), RobotMac(1), 500), 5 * kNsPerMs);
  std::vector<Delivery> out;
  medium.AdvanceTo(10 * kNsPerMs, &out);
  ASSERT_EQ(out.size(), 2u);
  // 6 dBm - (46.6777 + 30 dB) at B; 16.0206 dBm - 76.6777 dB at A.
  EXPECT_NEAR(out[0].rx_power_dbm, 6 - 76.6777, 1e-3);
  EXPECT_NEAR(out[1].rx_power_dbm, 16.0206 - 76.6777, 1e-3);
  const std::vector<TxRecord> txs = DrainTransmissions(medium);
  ASSERT_EQ(txs.size(), 4u);
  EXPECT_EQ(txs[0].rate_mbps, 12);  // A's DATA at its own rate,
  EXPECT_EQ(txs[1].rate_mbps, 12);  // answered at the control rate of 12 Mb/s;
  EXPECT_EQ(txs[2].rate_mbps, 54);  // B at the medium's rate,
  EXPECT_EQ(txs[3].rate_mbps, 24);  // answered at 24 Mb/s.
  EXPECT_THROW(medium.AddStation(RobotMac(2), {}, StationRadio{std::nullopt, 11.0}), Error);
  // A power no formula can take is a bug of the caller (the scenario bounds it at load).
  EXPECT_DEATH(medium.AddStation(RobotMac(2), {}, StationRadio{NAN, std::nullopt}), "isfinite");
}

// Rates of the DATA frames of `frames` frames over a `distance_m` 11a link.
std::vector<double> IdealRates(double distance_m, int frames) {
  MediumConfig config;
  config.rate_control = MediumConfig::RateControl::kIdeal;
  Medium medium(config);
  medium.AddStation(RobotMac(0), {0, 0, 0});
  medium.AddStation(RobotMac(1), {distance_m, 0, 0});
  medium.EnableTrace(true);
  for (int i = 0; i < frames; ++i) {
    medium.SubmitFrame(0, MakeEthernetFrame(RobotMac(1), RobotMac(0), 1500), i * 5 * kNsPerMs);
  }
  medium.AdvanceTo(frames * 5 * kNsPerMs, nullptr);
  std::vector<double> rates;
  for (const TxRecord& tx : DrainTransmissions(medium)) {
    if (tx.kind == FrameKind::kData) rates.push_back(tx.rate_mbps);
  }
  return rates;
}

TEST(RateControlTest, IdealStartsLowThenFollowsTheReportedSnr) {
  // ns-3: m_lastSnrObserved starts at 0, so the first frame goes at the
  // lowest rate; the ACK carries the SNR B measured and the next frames go at
  // the highest rate whose SNR for BER 1e-6 is below it. The rate falls with
  // distance. At 65 m (-86.9 dBm, under preamble detection) no ACK ever
  // returns an SNR, so it stays at the lowest rate.
  double previous = 1e9;
  for (double distance_m : {5.0, 20.0, 35.0, 50.0, 65.0}) {
    const std::vector<double> rates = IdealRates(distance_m, 20);
    ASSERT_GE(rates.size(), 20u);
    EXPECT_EQ(rates.front(), 6) << distance_m;
    const double settled = rates.back();
    for (size_t i = 1; i < rates.size(); ++i) EXPECT_EQ(rates[i], settled) << distance_m;
    EXPECT_LE(settled, previous) << distance_m;
    previous = settled;
  }
  EXPECT_EQ(IdealRates(5, 3).back(), 54);  // SNR 45 dB.
  EXPECT_EQ(IdealRates(65, 3).back(), 6);
}

}  // namespace
}  // namespace sitlnet::mac

// Path-loss models against their formulas: log-distance (ns-3
// LogDistancePropagationLossModel) and two-ray ground (ns-3 3.37
// TwoRayGroundPropagationLossModel::DoCalcRxPower; Rappaport, Wireless
// Communications, 2nd ed., 4.6). Expected values are worked out by hand from
// the formulas, with lambda = 299792458 / 5.15e9 = 0.0582121 m.
#include "mac_phy_sim/path_loss_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mac_phy_sim/channel.h"

namespace sitlnet::mac {
namespace {

PathLossLink Link(const Vec3d& a, const Vec3d& b) { return PathLossLink{0, 1, a, b, false}; }

TEST(TwoRayGroundTest, FriisBelowTheCrossover) {
  TwoRayGroundModel model(TwoRayGroundParams{});
  // Antennas at 2 m: crossover 4 pi 2 2 / lambda = 863.49 m.
  EXPECT_NEAR(model.CrossoverDistanceM(2, 2), 863.488, 1e-3);
  // Friis at 10 m: 20 log10(4 pi 10 / lambda) = 66.6839 dB.
  EXPECT_NEAR(model.LossDb(Link({0, 0, 2}, {10, 0, 2})), 66.6839, 1e-4);
}

TEST(TwoRayGroundTest, FourthPowerBeyondTheCrossover) {
  TwoRayGroundModel model(TwoRayGroundParams{});
  // Heights 2 and 3 m (crossover 1295 m would cover 1000 m): use 0.2 and 0.3 m,
  // crossover 12.95 m. At 1000 m: 40 log10(1000) - 20 log10(0.06) = 144.437 dB.
  EXPECT_NEAR(model.LossDb(Link({0, 0, 0.2}, {1000, 0, 0.3})), 120 - 20 * std::log10(0.06),
              1e-3);
  EXPECT_NEAR(model.LossDb(Link({0, 0, 0.2}, {1000, 0, 0.3})), 144.437, 1e-3);
}

TEST(TwoRayGroundTest, ContinuousAtTheCrossover) {
  // Both expressions meet at d = 4 pi ht hr / lambda.
  TwoRayGroundModel model(TwoRayGroundParams{});
  const double cross_m = model.CrossoverDistanceM(1, 1.5);
  const double below = model.LossDb(Link({0, 0, 1}, {cross_m * (1 - 1e-9), 0, 1.5}));
  const double above = model.LossDb(Link({0, 0, 1}, {cross_m * (1 + 1e-9), 0, 1.5}));
  EXPECT_NEAR(below, above, 1e-6);
}

TEST(TwoRayGroundTest, HeightAboveZSystemLossAndMinDistance) {
  TwoRayGroundParams params;
  params.height_above_z_m = 0.2;
  params.system_loss = 2;  // Linear: +3.0103 dB.
  params.min_distance_m = 5;
  TwoRayGroundModel model(params);
  // z = 0 and 0.1 m: antennas at 0.2 and 0.3 m, as above, plus the system loss.
  EXPECT_NEAR(model.LossDb(Link({0, 0, 0}, {1000, 0, 0.1})), 144.437 + 3.0103, 1e-3);
  // ns-3 gives the transmitted power at or below MinDistance.
  EXPECT_EQ(model.LossDb(Link({0, 0, 0}, {5, 0, 0})), 0);
  EXPECT_GT(model.LossDb(Link({0, 0, 0}, {5.01, 0, 0})), 0);
}

TEST(TwoRayGroundTest, ChannelAddsObstacleShadowing) {
  // The chain: two-ray, then Sommer's loss of the box (2 walls + 0.4 dB/m x 2 m).
  RadioChannel channel(std::make_unique<TwoRayGroundModel>(TwoRayGroundParams{}), true, 9, 0.4);
  const int a = channel.AddStation({0, 0, 2});
  const int b = channel.AddStation({10, 0, 2});
  channel.AddObstacle(Box{{5, 0, 2}, {2, 10, 10}, 0});
  EXPECT_NEAR(channel.LossDb(a, b), 66.6839 + 18.8, 1e-4);
  EXPECT_NEAR(channel.PathLossDb(a, b), 66.6839, 1e-4);
}

TEST(LogDistanceTest, ChannelMatchesTheModel) {
  RadioChannel channel(46.6777, 3, true, 9, 0.4);
  const int a = channel.AddStation({0, 0, 0});
  const int b = channel.AddStation({0, 100, 0});
  EXPECT_NEAR(channel.LossDb(a, b), 46.6777 + 60, 1e-9);
  EXPECT_NEAR(channel.PathLossDb(a, b), 46.6777 + 60, 1e-9);
}

}  // namespace
}  // namespace sitlnet::mac

// Path loss and Sommer et al. obstacle shadowing (docs/references.md#radio-defaults,
// #obstacle-shadowing).
#include "mac_phy_sim/channel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace sitlnet::mac {
namespace {

TEST(ChannelTest, BoxAcrossThePathCosts26Db) {
  // 20 m box fully across the path: 2 walls * 9 + 0.4 * 20 = 26 dB.
  const Box box{{50, 0, 0}, {20, 10, 10}, 0};
  const BoxCrossing c = CrossBox(box, {0, 0, 0}, {100, 0, 0});
  EXPECT_EQ(c.walls, 2);
  EXPECT_NEAR(c.inside_m, 20, 1e-9);
  RadioChannel channel(46.6777, 3, true, 9, 0.4);
  channel.AddObstacle(box);
  EXPECT_NEAR(channel.ShadowingDb({0, 0, 0}, {100, 0, 0}), 26, 1e-9);
}

TEST(ChannelTest, TransmitterInsideTheBoxCosts13Db) {
  // From the centre of that box: 1 wall + 10 m inside = 13 dB.
  RadioChannel channel(46.6777, 3, true, 9, 0.4);
  channel.AddObstacle(Box{{50, 0, 0}, {20, 10, 10}, 0});
  EXPECT_NEAR(channel.ShadowingDb({50, 0, 0}, {100, 0, 0}), 13, 1e-9);
}

TEST(ChannelTest, YawedBoxUsesItsOwnAxes) {
  // A 20 x 2 box yawed 90 degrees lies along y: crossing it along x covers 2 m.
  const Box box{{0, 0, 0}, {20, 2, 10}, 90};
  const BoxCrossing c = CrossBox(box, {-10, 0, 0}, {10, 0, 0});
  EXPECT_EQ(c.walls, 2);
  EXPECT_NEAR(c.inside_m, 2, 1e-9);
  EXPECT_EQ(CrossBox(box, {-10, 5, 0}, {10, 5, 0}).walls, 2);
  EXPECT_EQ(CrossBox(box, {-10, 11, 0}, {10, 11, 0}).walls, 0);  // Beyond its end.
  EXPECT_EQ(CrossBox(box, {-10, 0, 6}, {10, 0, 6}).walls, 0);    // Above it.
}

TEST(ChannelTest, LogDistanceLoss) {
  const LogDistanceModel model(46.6777, 3);
  EXPECT_NEAR(model.LossAtDistanceDb(0.001), 46.6777, 1e-9);  // ns-3: reference loss below 1 m.
  EXPECT_NEAR(model.LossAtDistanceDb(10), 46.6777 + 30, 1e-9);
  EXPECT_NEAR(model.LossAtDistanceDb(100), 46.6777 + 60, 1e-9);
}

TEST(ChannelTest, GridAgreesWithBruteForce) {
  // 1000 random boxes: the grid traversal must find exactly what testing
  // every box finds, for random segments including ones outside the grid.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-200, 200), size(1, 30), yaw(0, 180);
  RadioChannel channel(46.6777, 3, true, 9, 0.4);
  std::vector<Box> boxes;
  for (int i = 0; i < 1000; ++i) {
    boxes.push_back(Box{{pos(rng), pos(rng), 0}, {size(rng), size(rng), 20}, yaw(rng)});
    channel.AddObstacle(boxes.back());
  }
  std::uniform_real_distribution<double> wide(-300, 300), height(-5, 15);
  for (int k = 0; k < 500; ++k) {
    const Vec3d a{wide(rng), wide(rng), height(rng)}, b{wide(rng), wide(rng), height(rng)};
    double expected = 0;
    for (const Box& box : boxes) {
      const BoxCrossing c = CrossBox(box, a, b);
      expected += 9 * c.walls + 0.4 * c.inside_m;
    }
    EXPECT_NEAR(channel.ShadowingDb(a, b), expected, 1e-6) << k;
  }
}

TEST(ChannelTest, CacheRecomputesOnlyMovedStations) {
  RadioChannel channel(40, 2, true, 9, 0.4);
  const int a = channel.AddStation({0, 0, 0});
  const int b = channel.AddStation({10, 0, 0});
  const int c = channel.AddStation({0, 10, 0});
  EXPECT_NEAR(channel.LossDb(a, b), 60, 1e-9);
  EXPECT_NEAR(channel.LossDb(b, a), 60, 1e-9);
  channel.SetPosition(b, {100, 0, 0});
  EXPECT_NEAR(channel.LossDb(a, b), 80, 1e-9);
  EXPECT_NEAR(channel.LossDb(a, c), 60, 1e-9);
  channel.AddObstacle(Box{{0, 5, 0}, {4, 2, 4}, 0});  // Between a and c.
  EXPECT_NEAR(channel.LossDb(a, c), 60 + 18 + 0.8, 1e-9);
}

}  // namespace
}  // namespace sitlnet::mac

// Obstacle culling (docs/physics.md): a robot on its tile's model flies exactly as on the model
// holding every obstacle. Oracle: the unculled World itself, compared bit for bit (==).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "physics_mujoco/obstacle_tiles.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using testing::ExpectSamePose;
using testing::MakeScenario;

constexpr double kG = 9.81;

std::string Box(double x, double y, double z, double sx, double sy, double sz, double yaw_deg) {
  return "obstacle { center_m { x: " + std::to_string(x) + " y: " + std::to_string(y) +
         " z: " + std::to_string(z) + " } size_m { x: " + std::to_string(sx) +
         " y: " + std::to_string(sy) + " z: " + std::to_string(sz) +
         " } yaw_deg: " + std::to_string(yaw_deg) + " }\n";
}

// Three robots in a world of about 100 obstacles:
// - flyer: 20 s at (7, 1.5) m/s through a field of boxes on a 16 m grid (its lane kept free),
//   spinning about z so its 36-ray lidar sweeps the boxes of neighbouring tiles;
// - slider: motors off, slides along the roof of a long box from x = -21 at 10 m/s; friction
//   (mu = 1: about 5 m to stop) takes it across x = -17.5, the edge of its 20 m tile's region
//   (tile -40..-20, hysteresis 2.5 m): it changes model while in contact;
// - rammer: flies at 2 m/s into a wall whose face is 0.136 m beyond x = 162.5, the edge of its
//   tile's region (140..160 + 2.5): its collision box (0.14 m ahead of the centre) hits a box
//   of the next tile 4 mm before its centre would cross, on the model of its own tile.
std::string CullingScenario() {
  std::string text =
      "robot { name: \"flyer\" position_m { x: -10 y: 1 z: 4 } "
      "lidar { rays: 36 max_range_m: 15 } }\n"
      "robot { name: \"slider\" position_m { x: -21 y: -80 z: 1.035 } }\n"
      "robot { name: \"rammer\" position_m { x: 150 y: 80 z: 3 } }\n";
  for (int i = 0; i <= 12; ++i) {
    for (int j = -3; j <= 3; ++j) {
      // Deterministic jitter, sizes and yaws so that boxes straddle tile borders at all angles.
      const double x = 16.0 * i + 5.0 * std::sin(1.7 * i + 0.3 * j);
      const double y = 16.0 * j + 5.0 * std::cos(0.9 * i - 1.3 * j);
      const double lane_y = 1 + 1.5 / 7 * (x + 10);
      if (std::abs(y - lane_y) < 5) continue;
      text += Box(x, y, 6, 3 + (i + j + 3) % 4, 2 + std::abs(i * j) % 3, 12, 23.0 * i - 41.0 * j);
    }
  }
  text += Box(60, -80, 0.5, 200, 4, 1, 0);  // the slider's table
  text += Box(10, -70, 6, 1, 1, 12, 0);     // only in tile -1's model: the slider must switch
  text += Box(162.5 + 0.14 - 0.004 + 1, 80, 3, 2, 8, 6, 0);  // the rammer's wall, 2 m thick
  return text;
}

double HoverSpeed(const proto::Airframe& airframe) {
  return std::sqrt(airframe.mass_kg() * kG / (4 * airframe.thrust_coefficient()));
}

void StartFlights(World* world) {
  const double w = HoverSpeed(world->airframe(0));
  // Pure yaw torque at hover thrust (faster CW rotors 3, 4: counter-clockwise spin).
  world->SetRotorSpeeds(
      0, {w * std::sqrt(0.995), w * std::sqrt(0.995), w * std::sqrt(1.005), w * std::sqrt(1.005)});
  world->SetVelocity(0, {7, 1.5, 0});
  world->SetVelocity(1, {10, 0, 0});  // motors off
  world->SetRotorSpeeds(2, {w, w, w, w});
  world->SetVelocity(2, {2, 0, 0});
}

WorldOptions Culled(double tile_m) {
  WorldOptions options;
  options.cull_tile_m = tile_m;
  return options;
}

WorldOptions Unculled() {
  WorldOptions options;
  options.cull_obstacles = false;
  return options;
}

TEST(CullingTest, TileModelsFlyBitIdenticalToTheModelWithEveryObstacle) {
  const Scenario scenario = MakeScenario(CullingScenario());
  const int obstacles = scenario.spec.obstacle_size();
  ASSERT_GT(obstacles, 60);
  World all(scenario, Unculled());
  World tiles20(scenario, Culled(20));
  WorldOptions lazy7 = Culled(7);
  lazy7.cull_tiles_compiled_up_front = 0;  // each tile model compiled in the step needing it
  World tiles7(scenario, lazy7);           // lidar reach 15 m > tile: many more switches
  std::vector<World*> worlds = {&all, &tiles20, &tiles7};
  for (World* world : worlds) StartFlights(world);
  // With 20 m tiles every tile model is compiled when the World is built, none in a step (a
  // compile there made the 64-robot flight's iteration 4x longer); the 7 m tiles' models are
  // compiled on first use (what happens beyond the up-front limit): both fly the same.
  const int compiled20 = tiles20.models_compiled(), compiled7 = tiles7.models_compiled();
  const int slider_obstacles_at_start = tiles20.obstacles_in_model(1);
  std::vector<float> want, got;
  int lidar_hits = 0;
  bool slider_flat = true, slider_crossed = false, rammer_stopped = false;
  for (int ms = 10; ms <= 20000; ms += 10) {
    for (World* world : worlds) world->Advance(10);
    for (int robot = 0; robot < 3; ++robot) {
      for (World* culled : {&tiles20, &tiles7}) {
        ExpectSamePose(all.Pose(robot), culled->Pose(robot),
                       "robot " + std::to_string(robot) + " at " + std::to_string(ms) + " ms");
      }
    }
    all.Lidar(0, &want);
    for (float range : want) lidar_hits += range < 15.0f;
    for (World* culled : {&tiles20, &tiles7}) {
      culled->Lidar(0, &got);
      ASSERT_EQ(want, got) << "lidar at " << ms << " ms";
      EXPECT_LT(culled->obstacles_in_model(0), obstacles);
    }
    if (::testing::Test::HasFailure()) return;  // one report, not thousands
    const RobotPose slider = all.Pose(1);
    slider_flat &= std::abs(slider.position_m.z - 1.035) < 0.03 && slider.orientation.w > 0.98;
    if (slider.velocity_m_s.x > 1) slider_crossed |= slider.position_m.x > -17.5;
    rammer_stopped |= std::abs(all.Pose(2).velocity_m_s.x) < 0.05;
  }
  // The flights did what the scenario means: the flyer crossed the field (past x = 120) seeing
  // boxes, the slider slid flat on the table across its region's edge, the rammer hit its wall.
  EXPECT_GT(all.Pose(0).position_m.x, 120);
  EXPECT_GT(lidar_hits, 1000);
  EXPECT_TRUE(slider_flat);
  EXPECT_TRUE(slider_crossed);
  EXPECT_NE(tiles20.obstacles_in_model(1), slider_obstacles_at_start);  // it changed model
  EXPECT_TRUE(rammer_stopped);
  EXPECT_LT(all.Pose(2).position_m.x, 162.5);
  EXPECT_EQ(all.model_switches(), 0);
  EXPECT_GT(tiles20.model_switches(), 8);
  EXPECT_GT(tiles7.model_switches(), tiles20.model_switches());
  EXPECT_GT(compiled20, 50);
  EXPECT_EQ(tiles20.models_compiled(), compiled20);
  EXPECT_GT(tiles7.models_compiled(), compiled7);
}

TEST(CullingTest, CulledWorldsAreDeterministicAndThreadIndependent) {
  const Scenario scenario = MakeScenario(CullingScenario());
  WorldOptions one = Culled(20);
  one.threads = 1;
  World a(scenario, Culled(20)), b(scenario, Culled(20)), c(scenario, one);
  for (World* world : {&a, &b, &c}) {
    StartFlights(world);
    world->Advance(8000);
  }
  for (int robot = 0; robot < 3; ++robot) {
    ExpectSamePose(a.Pose(robot), b.Pose(robot), "same options");
    ExpectSamePose(a.Pose(robot), c.Pose(robot), "1 thread");
  }
  // Reset and the same commands again: the same flight.
  const RobotPose first = a.Pose(0);
  a.ResetRobot(0);
  StartFlights(&a);
  a.Advance(8000);
  ExpectSamePose(first, a.Pose(0), "after reset");
}

TEST(CullingTest, FastRobotUsesTheModelWithEveryObstacle) {
  // 1 m per 1 ms step is the most a robot may travel on a tile model.
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 2 } }\n" +
                                         Box(100, 0, 2, 1, 1, 1, 0) + Box(-100, 0, 2, 1, 1, 1, 0));
  World world(scenario, Culled(20));
  EXPECT_EQ(world.obstacles_in_model(0), 0);
  world.SetVelocity(0, {1001, 0, 0});
  EXPECT_EQ(world.obstacles_in_model(0), 2);
  world.SetVelocity(0, {0, 0, 0});
  EXPECT_EQ(world.obstacles_in_model(0), 0);
}

TEST(CullingTest, TilesWithTheSameObstaclesShareOneModel) {
  // 100 m east over open ground (5 tiles of 20 m), one box far north: every tile on the way
  // has no obstacle, so after the start (the model with every obstacle, then the ground-only
  // one) the robot never changes model. Compiled: those two (the tiles around the box hold
  // every obstacle: they use the model with all).
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { x: 1 y: 1 z: 2 } }\n" +
                                         Box(50, 500, 2, 1, 1, 1, 0));
  World world(scenario, Culled(20));
  const double w = HoverSpeed(world.airframe(0));
  world.SetRotorSpeeds(0, {w, w, w, w});
  world.SetVelocity(0, {10, 0, 0});
  world.Advance(10000);
  EXPECT_GT(world.Pose(0).position_m.x, 100);
  EXPECT_EQ(world.obstacles_in_model(0), 0);
  EXPECT_EQ(world.model_switches(), 1);
  EXPECT_EQ(world.models_compiled(), 2);
}

TEST(ObstacleTilesTest, TileModelsHoldTheBoxesWithinReachOfTheRegionYawIncluded) {
  // Tile 8 m: hysteresis 1 m; reach 5 m; margin 1 + 5 + 1 (safety) = 7 m. Tile (0, 0) keeps
  // obstacles whose bounding box reaches into [-7, 15] x [-7, 15].
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 2 } }\n" +
      Box(17, 4, 1, 2, 2, 1, 0) +     // spans x 16..18: out
      Box(15.9, 4, 1, 2, 2, 1, 0) +   // spans x 14.9..16.9: in
      Box(18, 4, 1, 4, 0.1, 1, 90) +  // turned 90 deg: spans x 17.95..18.05: out
      Box(18, 4, 1, 8, 0.1, 1, 45) +  // 45 deg: x 18 -+ (4 + 0.05) / sqrt 2 = 15.14..: out
      Box(17, 4, 1, 8, 0.1, 1, 45) +  // x from 17 - 2.86 = 14.14: in
      Box(4, -9, 1, 2, 2, 1, 0));     // y -10..-8: out
  const ObstacleTiles tiles(scenario, 8, 5);
  EXPECT_EQ(tiles.hysteresis_m(), 1);
  EXPECT_EQ(tiles.margin_m(), 7);
  EXPECT_EQ(tiles.ObstaclesOf({0, 0}), (std::vector<int>{1, 4}));
  // The neighbour (1, 0) spans x 8..16, its models reach to x 23: all but the last.
  EXPECT_EQ(tiles.ObstaclesOf({1, 0}), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(tiles.TileOf(-0.5, 8.0).ix, -1);
  EXPECT_EQ(tiles.TileOf(-0.5, 8.0).iy, 1);
  const Rect region = tiles.Region({0, 0});
  EXPECT_TRUE(region.Contains(-1, 9));
  EXPECT_FALSE(region.Contains(-1.01, 4));
  EXPECT_FALSE(region.Contains(std::nan(""), 4));
  EXPECT_FALSE(tiles.HasTile(std::nan(""), 0));
  EXPECT_FALSE(tiles.HasTile(0, 2e9));
}

TEST(ObstacleTilesTest, TilesNearObstaclesAreExactlyThoseWhoseModelsHoldOne) {
  const Scenario scenario =
      MakeScenario("robot { name: \"a\" position_m { z: 2 } }\n" + Box(17, 4, 1, 2, 2, 1, 0) +
                   Box(-30, 12, 1, 8, 0.1, 1, 45) + Box(40.5, -40.5, 1, 1, 30, 1, 30));
  const ObstacleTiles tiles(scenario, 8, 5);
  // Oracle: every tile of a grid far wider than the boxes' reach, asked one by one.
  std::vector<TileIndex> want;
  for (int64_t ix = -30; ix <= 30; ++ix) {
    for (int64_t iy = -30; iy <= 30; ++iy) {
      if (!tiles.ObstaclesOf({ix, iy}).empty()) want.push_back({ix, iy});
    }
  }
  ASSERT_GT(want.size(), 20u);
  const auto near = tiles.TilesNearObstacles(10000);
  ASSERT_TRUE(near.has_value());
  EXPECT_EQ(*near, want);
  EXPECT_FALSE(tiles.TilesNearObstacles(static_cast<int64_t>(want.size()) - 1).has_value());
  // A box 100 km wide: too many tiles to list, found out without walking them all.
  const Scenario wide =
      MakeScenario("robot { name: \"a\" position_m { z: 2 } }\n" + Box(0, 0, 1, 1e5, 1e5, 1, 0));
  EXPECT_FALSE(ObstacleTiles(wide, 20, 15).TilesNearObstacles(1024).has_value());
}

}  // namespace
}  // namespace sitlnet::physics

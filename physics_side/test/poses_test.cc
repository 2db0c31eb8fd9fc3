// PosesFromWorld: what physics reports to the coordinator (and a node host to its central host,
// issue 35). Oracle: World::Pose of each robot, the doubles trajectories.csv is written from.
#include <gtest/gtest.h>

#include "physics_side/physics_side.h"

namespace sitlnet::physics_side {
namespace {

TEST(PosesFromWorldTest, ASliceReportsItsRobotsInIndexOrderWithVelocities) {
  const Scenario scenario = LoadScenarioText(
      "name: \"pfw\"\n"
      "robot { name: \"a\" position_m { z: 5 } }\n"
      "robot { name: \"b\" position_m { x: 3 z: 5 } yaw_deg: 30 }\n"
      "robot { name: \"c\" position_m { x: 6 z: 5 } }\n"
      "robot { name: \"d\" position_m { x: 9 z: 5 } yaw_deg: -60 }\n",
      "pfw.textproto");
  physics::WorldOptions options;
  options.robots = {1, 3};
  physics::World world(scenario, options);
  world.SetVelocity(1, {1.5, -2, 0.25});
  world.SetVelocity(3, {-0.5, 0, 1});
  world.Advance(100);  // Falling and drifting: every component moves.
  proto::coord::Poses poses;
  PosesFromWorld(world, &poses);
  ASSERT_EQ(poses.position_m_size(), 6);
  ASSERT_EQ(poses.orientation_wxyz_size(), 8);
  ASSERT_EQ(poses.velocity_m_s_size(), 6);
  for (int k = 0; k < 2; ++k) {
    const physics::RobotPose pose = world.Pose(world.robots()[k]);
    EXPECT_EQ(poses.position_m(3 * k), pose.position_m.x);
    EXPECT_EQ(poses.position_m(3 * k + 1), pose.position_m.y);
    EXPECT_EQ(poses.position_m(3 * k + 2), pose.position_m.z);
    EXPECT_EQ(poses.orientation_wxyz(4 * k), pose.orientation.w);
    EXPECT_EQ(poses.orientation_wxyz(4 * k + 3), pose.orientation.z);
    EXPECT_EQ(poses.velocity_m_s(3 * k), pose.velocity_m_s.x);
    EXPECT_EQ(poses.velocity_m_s(3 * k + 1), pose.velocity_m_s.y);
    EXPECT_EQ(poses.velocity_m_s(3 * k + 2), pose.velocity_m_s.z);
  }
  // Robot 1 first (x from 3), then robot 3 (x from 9); 0.1 s of free fall: vz near -1 m/s.
  EXPECT_NEAR(poses.position_m(0), 3.15, 1e-9);
  EXPECT_NEAR(poses.position_m(3), 9 - 0.05, 1e-9);
  EXPECT_NEAR(poses.velocity_m_s(2), 0.25 - 0.981, 1e-9);
}

}  // namespace
}  // namespace sitlnet::physics_side

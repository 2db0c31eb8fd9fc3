// Flight physics against closed-form oracles (issue 5): hover, free fall, yaw, collision,
// lidar, IMU at rest, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "physics_mujoco/frames.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using testing::MakeScenario;

constexpr double kG = 9.81;  // MuJoCo's gravity in our models (world_builder.cc)

double HoverSpeed(const proto::Airframe& airframe) {
  return std::sqrt(airframe.mass_kg() * kG / (4 * airframe.thrust_coefficient()));
}

void SetHover(World* world, int robot) {
  const double w = HoverSpeed(world->airframe(robot));
  world->SetRotorSpeeds(robot, {w, w, w, w});
}

TEST(WorldTest, HoverAtOmegaHoverHoldsAltitudeWithinOneCentimetreForTenSeconds) {
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 5 } }");
  World world(scenario);
  SetHover(&world, 0);
  double worst_m = 0;
  for (int ms = 0; ms < 10000; ms += 10) {
    world.Advance(10);
    worst_m = std::max(worst_m, std::abs(world.Pose(0).position_m.z - 5));
  }
  EXPECT_EQ(world.time_ns(0), 10 * kNsPerS);
  EXPECT_LT(worst_m, 0.01);
  EXPECT_NEAR(world.Pose(0).position_m.x, 0, 0.01);
  EXPECT_NEAR(world.Pose(0).position_m.y, 0, 0.01);
}

TEST(WorldTest, CrazyflieSizedAirframeHoversToo) {
  // The 27 g airframe of docs/physics.md (gym-pybullet-drones' Crazyflie 2 figures).
  const Scenario scenario = MakeScenario(
      "airframe { name: \"cf2\" mass_kg: 0.027 arm_x_m: 0.02807 arm_y_m: 0.02807 "
      "ixx_kg_m2: 1.4e-5 iyy_kg_m2: 1.4e-5 izz_kg_m2: 2.17e-5 thrust_coefficient: 2.8816e-8 "
      "drag_coefficient: 7.2404e-10 max_rotor_speed_rad_s: 2274 }\n"
      "robot { name: \"a\" airframe: \"cf2\" position_m { z: 1 } }");
  World world(scenario);
  SetHover(&world, 0);
  world.Advance(10000);
  EXPECT_NEAR(world.Pose(0).position_m.z, 1, 0.01);
}

// A ground station has no physics: in the air without thrust it does not fall, its motors do
// nothing, and its clock is the world's.
TEST(WorldTest, AGroundStationStaysWhereItIsWhileTheClockRuns) {
  const Scenario scenario =
      MakeScenario("robot { name: \"gcs\" position_m { x: 3 y: 4 z: 10 } ground_station: true }\n"
                   "robot { name: \"a\" position_m { z: 10 } }");
  World world(scenario);
  world.SetRotorSpeeds(0, {2000, 2000, 2000, 2000});
  world.Advance(500);
  EXPECT_EQ(world.steps(0), 500);
  EXPECT_EQ(world.Pose(0).position_m.x, 3);
  EXPECT_EQ(world.Pose(0).position_m.y, 4);
  EXPECT_EQ(world.Pose(0).position_m.z, 10);
  EXPECT_LT(world.Pose(1).position_m.z, 10 - 1);  // The robot beside it fell.
}

TEST(WorldTest, FreeFallMatchesHalfGTSquaredWithinOneMillimetre) {
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 20 } }");
  World world(scenario);
  for (int ms = 100; ms <= 1000; ms += 100) {
    world.Advance(100);
    const double t = ms / 1000.0;
    EXPECT_NEAR(world.Pose(0).position_m.z, 20 - kG * t * t / 2, 1e-3) << "t = " << t;
    EXPECT_NEAR(world.Pose(0).velocity_m_s.z, -kG * t, 1e-6) << "t = " << t;
  }
  // A falling IMU measures no specific force.
  const ImuSample imu = world.Imu(0);
  EXPECT_NEAR(imu.accel_m_s2.z, 0, 1e-6);
}

TEST(WorldTest, Rk4AtTwoMillisecondStepsMeetsTheFreeFallHoverAndWallOracles) {
  // Half the model evaluations of 1 ms steps (docs/performance.md): the same oracles hold.
  const Scenario fall = MakeScenario("robot { name: \"a\" position_m { z: 20 } }", "", 2000);
  World world(fall);
  world.Advance(500);  // 1 s
  EXPECT_EQ(world.time_ns(0), kNsPerS);
  EXPECT_NEAR(world.Pose(0).position_m.z, 20 - kG / 2, 1e-3);
  const Scenario hover = MakeScenario("robot { name: \"a\" position_m { z: 5 } }", "", 2000);
  World hovering(hover);
  SetHover(&hovering, 0);
  double worst_m = 0;
  for (int i = 0; i < 1000; ++i) {  // 10 s
    hovering.Advance(5);
    worst_m = std::max(worst_m, std::abs(hovering.Pose(0).position_m.z - 5));
  }
  EXPECT_LT(worst_m, 0.01);
  EXPECT_NEAR(hovering.Imu(0).accel_m_s2.z, kG, 1e-6);
  // Into a wall at 2 m/s (as QuadFlownIntoABoxStopsAgainstIt): the contact's 4 ms time
  // constant is two 2 ms steps, the least MuJoCo keeps; it still stops against the wall.
  const Scenario wall = MakeScenario(
      "robot { name: \"a\" position_m { z: 2 } }\n"
      "obstacle { name: \"wall\" center_m { x: 3 z: 2 } size_m { x: 1 y: 6 z: 4 } }",
      "", 2000);
  World ramming(wall);
  SetHover(&ramming, 0);
  ramming.SetVelocity(0, {2, 0, 0});
  double max_x = 0;
  for (int i = 0; i < 300; ++i) {  // 3 s
    ramming.Advance(5);
    max_x = std::max(max_x, ramming.Pose(0).position_m.x);
  }
  const double contact_x = 2.5 - 0.14;
  EXPECT_GT(max_x, contact_x - 0.01);
  EXPECT_LT(max_x, contact_x + 0.02);
  EXPECT_LT(std::abs(ramming.Pose(0).velocity_m_s.x), 0.05);
}

TEST(WorldTest, SemiImplicitEulerLagsFreeFallByHalfGTDt) {
  // Documents why RK4 is the default: Euler's position error is g t dt / 2 (4.9 mm here).
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 20 } }");
  World world(scenario, WorldOptions{Integrator::kEuler, 1});
  world.Advance(1000);
  EXPECT_NEAR(world.Pose(0).position_m.z, 20 - kG / 2 - kG * 1.0 * 0.001 / 2, 1e-9);
}

TEST(WorldTest, TheScenarioChoosesTheIntegratorAndOptionsOverrideIt) {
  const std::string robot = "robot { name: \"a\" position_m { z: 20 } }";
  const Scenario euler = MakeScenario(robot, "physics_integrator: INTEGRATOR_EULER");
  const Scenario rk4 = MakeScenario(robot, "physics_integrator: INTEGRATOR_RK4");
  const double exact_m = 20 - kG / 2;         // after 1 s of free fall
  const double euler_lag_m = kG * 0.001 / 2;  // g t dt / 2
  const Scenario default_scenario = MakeScenario(robot);  // A World keeps its scenario's address.
  World from_scenario(euler);
  World overridden(euler, WorldOptions{Integrator::kRk4, 1});
  World default_rk4(default_scenario);
  World rk4_overridden(rk4, WorldOptions{Integrator::kEuler, 1});
  for (World* world : {&from_scenario, &overridden, &default_rk4, &rk4_overridden}) {
    world->Advance(1000);
  }
  EXPECT_NEAR(from_scenario.Pose(0).position_m.z, exact_m - euler_lag_m, 1e-9);
  EXPECT_NEAR(overridden.Pose(0).position_m.z, exact_m, 1e-9);
  EXPECT_NEAR(default_rk4.Pose(0).position_m.z, exact_m, 1e-9);
  EXPECT_NEAR(rk4_overridden.Pose(0).position_m.z, exact_m - euler_lag_m, 1e-9);
}

// Speeds up one diagonal pair and slows the other keeping total thrust: pure yaw torque.
void YawCommand(World* world, bool speed_up_cw) {
  const double w = HoverSpeed(world->airframe(0));
  const double fast = w * std::sqrt(1.1);
  const double slow = w * std::sqrt(0.9);
  // Rotors 1, 2 spin CCW; 3, 4 CW (ArduPilot quad-X).
  if (speed_up_cw) {
    world->SetRotorSpeeds(0, {slow, slow, fast, fast});
  } else {
    world->SetRotorSpeeds(0, {fast, fast, slow, slow});
  }
}

TEST(WorldTest, FasterClockwiseRotorsYawTheBodyCounterClockwise) {
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 5 } }");
  for (bool cw : {true, false}) {
    World world(scenario);
    YawCommand(&world, cw);
    world.Advance(500);
    const RobotPose pose = world.Pose(0);
    // Reaction torque of faster CW rotors is counter-clockwise seen from above: +z (ENU).
    const double expected_sign = cw ? 1.0 : -1.0;
    EXPECT_GT(expected_sign * pose.angular_velocity_rad_s.z, 0.1);
    EXPECT_GT(expected_sign * YawRad(pose.orientation), 0.01);
    EXPECT_NEAR(pose.position_m.z, 5, 0.01);  // thrust unchanged
  }
}

TEST(WorldTest, LinearDragDecaysVelocityExponentially) {
  // m dv/dt = -c v: v(t) = v0 exp(-c t / m) (the drag force is held over each 1 ms step:
  // relative error ~ (c dt / m) t c / (2 m) = 7e-5 here).
  const Scenario scenario = MakeScenario(
      "airframe { name: \"draggy\" linear_drag_n_s_per_m: 0.5 }\n"
      "robot { name: \"a\" airframe: \"draggy\" position_m { z: 5 } }");
  World world(scenario);
  SetHover(&world, 0);
  world.SetVelocity(0, {2, 0, 0});
  world.Advance(1000);
  const double expected = 2 * std::exp(-0.5 * 1.0 / world.airframe(0).mass_kg());
  EXPECT_NEAR(world.Pose(0).velocity_m_s.x, expected, 1e-3 * expected);
}

TEST(WorldTest, QuadFlownIntoABoxStopsAgainstIt) {
  // Box faces at x = 2.5; the quad's collision box reaches 0.14 m ahead of its centre.
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 2 } }\n"
      "obstacle { name: \"wall\" center_m { x: 3 z: 2 } size_m { x: 1 y: 6 z: 4 } }");
  World world(scenario);
  SetHover(&world, 0);
  world.SetVelocity(0, {2, 0, 0});
  double max_x = 0;
  for (int ms = 0; ms < 3000; ms += 10) {
    world.Advance(10);
    max_x = std::max(max_x, world.Pose(0).position_m.x);
  }
  const double contact_x = 2.5 - 0.14;
  EXPECT_GT(max_x, contact_x - 0.01);  // it got there
  // and did not go through: MuJoCo's soft contact lets it in by about speed x 4 ms.
  EXPECT_LT(max_x, contact_x + 0.02);
  EXPECT_LT(world.Pose(0).position_m.x, contact_x + 0.02);
  // Stopped: under 2.5 % of the 2 m/s it hit with remains (a small rebound).
  EXPECT_LT(std::abs(world.Pose(0).velocity_m_s.x), 0.05);
}

TEST(WorldTest, AdvancingInOneCallOrStepByStepGivesTheSameFlightAndImu) {
  // World evaluates the accelerometer only in the last step of an Advance call (the others run
  // on a copy of the model with sensors off): 10 calls of 1 step must equal 1 call of 10, for
  // the pose and for the IMU, here through a collision (contact forces in the accelerometer).
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 2 } }\n"
      "obstacle { name: \"wall\" center_m { x: 3 z: 2 } size_m { x: 1 y: 6 z: 4 } }");
  World by_call(scenario), by_step(scenario);
  for (World* world : {&by_call, &by_step}) {
    SetHover(world, 0);
    world->SetVelocity(0, {2, 0, 0});
  }
  for (int ms = 0; ms < 2000; ms += 10) {
    by_call.Advance(10);
    for (int s = 0; s < 10; ++s) by_step.Advance(1);
    const ImuSample a = by_call.Imu(0), b = by_step.Imu(0);
    ASSERT_EQ(a.accel_m_s2.x, b.accel_m_s2.x) << ms;
    ASSERT_EQ(a.accel_m_s2.y, b.accel_m_s2.y) << ms;
    ASSERT_EQ(a.accel_m_s2.z, b.accel_m_s2.z) << ms;
    ASSERT_EQ(a.gyro_rad_s.y, b.gyro_rad_s.y) << ms;
    ASSERT_EQ(by_call.Pose(0).position_m.x, by_step.Pose(0).position_m.x) << ms;
    ASSERT_EQ(by_call.Pose(0).orientation.y, by_step.Pose(0).orientation.y) << ms;
  }
  // The collision happened (contact force along x in the accelerometer at some point).
  EXPECT_GT(by_call.Pose(0).position_m.x, 2.3);
}

TEST(WorldTest, LidarRayReturnsTheDistanceToABox) {
  // Box face at x = 4 (centre 5, size 2); 4 rays over 360 deg: -180, -90, 0 (nose), 90.
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 2 } lidar { rays: 4 max_range_m: 20 } }\n"
      "robot { name: \"b\" position_m { x: 5 y: -3 z: 2 } yaw_deg: 90 lidar { rays: 4 } }\n"
      "obstacle { center_m { x: 5 z: 2 } size_m { x: 2 y: 2 z: 4 } }");
  World world(scenario);
  std::vector<float> ranges;
  world.Lidar(0, &ranges);
  ASSERT_EQ(ranges.size(), 4u);
  EXPECT_NEAR(ranges[2], 4.0, 1e-5);
  EXPECT_EQ(ranges[0], 20.0f);
  EXPECT_EQ(ranges[1], 20.0f);
  EXPECT_EQ(ranges[3], 20.0f);
  // Robot b faces north (yaw 90) from 3 m south of the box centre: face at 2 m.
  world.Lidar(1, &ranges);
  EXPECT_NEAR(ranges[2], 2.0, 1e-5);
  // Its ray at -90 deg (to its right, east) hits nothing.
  EXPECT_EQ(ranges[1], 20.0f);
}

TEST(WorldTest, ImuAtHoverReadsPlusGOnBodyZ) {
  const Scenario scenario = MakeScenario("robot { name: \"a\" position_m { z: 5 } }");
  World world(scenario);
  SetHover(&world, 0);
  world.Advance(100);
  const ImuSample imu = world.Imu(0);
  EXPECT_NEAR(imu.accel_m_s2.z, kG, 1e-6);
  EXPECT_NEAR(imu.accel_m_s2.x, 0, 1e-9);
  EXPECT_NEAR(imu.gyro_rad_s.z, 0, 1e-9);
}

TEST(WorldTest, ImuNoiseIsSeededAndDiffersPerRobot) {
  const std::string robots =
      "robot { name: \"a\" position_m { z: 5 } imu { gyro_noise_rad_s: 0.01 "
      "accel_bias_m_s2: 0.1 } }\n"
      "robot { name: \"b\" position_m { z: 5 } imu { gyro_noise_rad_s: 0.01 "
      "accel_bias_m_s2: 0.1 } }\n";
  const Scenario scenario = MakeScenario(robots);
  World first(scenario);
  World second(scenario);
  const ImuSample a1 = first.Imu(0), a2 = second.Imu(0), b1 = first.Imu(1);
  EXPECT_EQ(a1.gyro_rad_s.x, a2.gyro_rad_s.x);
  EXPECT_EQ(a1.accel_m_s2.z, a2.accel_m_s2.z);
  EXPECT_NE(a1.gyro_rad_s.x, 0);
  EXPECT_NE(a1.gyro_rad_s.x, b1.gyro_rad_s.x);
}

// PhysicsServer steps each robot as its own autopilot answers (docs/physics.md, "Stepping an
// iteration"): robots advanced apart, each in its own chunks, fly bit for bit as robots
// advanced together, on one thread or two.
TEST(WorldTest, RobotsAdvancedApartFlyAsRobotsAdvancedTogether) {
  std::string robots;
  for (int i = 0; i < 5; ++i) {
    robots += "robot { name: \"r" + std::to_string(i) + "\" position_m { x: " +
              std::to_string(2 * i) + " z: 3 } }\n";
  }
  const Scenario scenario = MakeScenario(robots);
  for (const int threads : {1, 2}) {
    World together(scenario);
    World apart(scenario, WorldOptions{Integrator::kRk4, threads});
    for (World* world : {&together, &apart}) {
      for (int i = 0; i < 5; ++i) world->SetRotorSpeeds(i, {900.0 + i, 1000, 1010, 995});
    }
    // Robot i in chunks of i + 1 steps (robot 4: 5 at a time), the robots listed in turn.
    int64_t left[5] = {100, 100, 100, 100, 100};
    for (bool stepping = true; stepping;) {
      stepping = false;
      std::vector<RobotSteps> chunk;
      for (int i = 4; i >= 0; --i) {
        const int steps = static_cast<int>(std::min<int64_t>(i + 1, left[i]));
        if (steps == 0) continue;
        chunk.push_back({i, steps});
        left[i] -= steps;
        stepping = true;
      }
      apart.Advance(chunk);
    }
    together.Advance(100);
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(apart.steps(i), 100);
      testing::ExpectSamePose(together.Pose(i), apart.Pose(i), "robot " + std::to_string(i));
      const ImuSample a = together.Imu(i), b = apart.Imu(i);
      EXPECT_EQ(a.accel_m_s2.z, b.accel_m_s2.z) << i;
      EXPECT_EQ(a.gyro_rad_s.x, b.gyro_rad_s.x) << i;
    }
  }
}

TEST(WorldTest, ThreadCountDoesNotChangeResults) {
  std::string robots;
  for (int i = 0; i < 7; ++i) {
    robots += "robot { name: \"r" + std::to_string(i) + "\" position_m { x: " + std::to_string(i) +
              " z: 3 } }\n";
  }
  const Scenario scenario = MakeScenario(robots);
  World one(scenario, WorldOptions{Integrator::kRk4, 1});
  World two(scenario, WorldOptions{Integrator::kRk4, 2});
  for (World* world : {&one, &two}) {
    for (int i = 0; i < 7; ++i) world->SetRotorSpeeds(i, {900.0 + i, 1000, 1010, 995});
    world->Advance(300);
  }
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(one.Pose(i).position_m.x, two.Pose(i).position_m.x);
    EXPECT_EQ(one.Pose(i).orientation.z, two.Pose(i).orientation.z);
  }
}

}  // namespace
}  // namespace sitlnet::physics

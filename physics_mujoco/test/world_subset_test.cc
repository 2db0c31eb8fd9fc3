// A World of some of the scenario's robots (a node host's, issue 35) flies them exactly as the
// World of every robot does. Oracle: the whole World itself, compared bit for bit (==).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cerrno>
#include <string>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/test_scenarios.h"
#include "robot_images/flocker/controller.h"

namespace sitlnet::physics {
namespace {

using testing::ExpectSamePose;
using testing::MakeScenario;

// Four robots with IMU noise and bias (each robot's own seeded draws) and a lidar, flying east
// past boxes that their lidars see and that lie in other obstacle tiles than their start.
std::string FourRobots() {
  std::string text;
  for (int i = 0; i < 4; ++i) {
    text += "robot { name: \"r" + std::to_string(i) + "\" position_m { x: " +
            std::to_string(-4 + 3 * i) + " y: " + std::to_string(6 * i) +
            " z: 0.2 } imu { gyro_noise_rad_s: 0.02 gyro_bias_rad_s: 0.01 "
            "accel_noise_m_s2: 0.1 } lidar { rays: 16 max_range_m: 12 } }\n";
    text += "obstacle { center_m { x: " + std::to_string(14 + 2 * i) + " y: " +
            std::to_string(6 * i + 3) + " z: 2 } size_m { x: 2 y: 1 z: 4 } yaw_deg: 30 }\n";
  }
  return text;
}

// One 100 Hz update of the flocker image's controller (robot_images/flocker) for `robot`: its
// pose, its noisy gyro as the body rates (one IMU draw), and a velocity and altitude of its
// own. The airframe is the default one, as AirframeParams' defaults.
void Control(World* world, int robot) {
  const RobotPose pose = world->Pose(robot);
  const ImuSample imu = world->Imu(robot);
  flocker::VehicleState state;
  state.position_m = {pose.position_m.x, pose.position_m.y, pose.position_m.z};
  state.velocity_m_s = {pose.velocity_m_s.x, pose.velocity_m_s.y, pose.velocity_m_s.z};
  state.orientation = Eigen::Quaterniond(pose.orientation.w, pose.orientation.x,
                                         pose.orientation.y, pose.orientation.z);
  state.angular_velocity_rad_s = {imu.gyro_rad_s.x, imu.gyro_rad_s.y, imu.gyro_rad_s.z};
  const Eigen::Vector2d velocity_m_s(3.0 + robot, 0.2 * (robot - 1.5));
  world->SetRotorTarget(robot, flocker::ComputeRotorSpeeds(flocker::AirframeParams{},
                                                           flocker::ControllerGains{}, state,
                                                           velocity_m_s, 2.0 + 0.5 * robot, 0));
}

TEST(WorldSubsetTest, RobotsOneAndThreeAloneFlyBitIdenticalToTheWorldOfAllFour) {
  const Scenario scenario = MakeScenario(FourRobots());
  World all(scenario);
  WorldOptions some;
  some.robots = {1, 3};
  World subset(scenario, some);
  EXPECT_EQ(all.robots(), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(subset.robots(), (std::vector<int>{1, 3}));
  EXPECT_EQ(subset.robot_count(), 2);
  EXPECT_FALSE(subset.simulates(0));
  EXPECT_TRUE(subset.simulates(3));
  std::vector<float> want, got;
  int lidar_hits = 0;
  for (int ms = 10; ms <= 5000; ms += 10) {
    for (int robot : all.robots()) Control(&all, robot);
    for (int robot : subset.robots()) Control(&subset, robot);
    all.Advance(10);
    subset.Advance(10);
    for (int robot : subset.robots()) {
      const std::string where = "robot " + std::to_string(robot) + " at " + std::to_string(ms);
      ExpectSamePose(all.Pose(robot), subset.Pose(robot), where + " ms");
      all.Lidar(robot, &want);
      subset.Lidar(robot, &got);
      ASSERT_EQ(want, got) << "lidar of " << where << " ms";
      for (float range : want) lidar_hits += range < 12.0f;
    }
    if (::testing::Test::HasFailure()) return;  // one report, not hundreds
  }
  EXPECT_EQ(subset.now_ns(), 5 * kNsPerS);
  EXPECT_EQ(subset.time_ns(3), all.time_ns(0));
  // The flights did what they mean: up to their altitudes, east at several m/s, past boxes.
  for (int robot : subset.robots()) {
    const RobotPose pose = subset.Pose(robot);
    EXPECT_NEAR(pose.position_m.z, 2.0 + 0.5 * robot, 0.3) << robot;
    EXPECT_GT(pose.velocity_m_s.x, 2.0) << robot;
  }
  EXPECT_GT(lidar_hits, 50);
}

TEST(WorldSubsetTest, RobotsMustBeAscendingIndicesOfTheScenario) {
  const Scenario scenario = MakeScenario(FourRobots());
  for (const std::vector<int>& robots :
       std::vector<std::vector<int>>{{3, 1}, {1, 1}, {4}, {-1, 2}}) {
    WorldOptions options;
    options.robots = robots;
    try {
      World world(scenario, options);
      ADD_FAILURE() << "accepted robots starting " << robots.front();
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("a slice holds ascending indices below 4"), std::string::npos)
          << error.what();
    }
  }
}

// Binds a UDP socket on `address`:`port` (no SO_REUSEADDR); returns errno, 0 on success.
int BindError(const char* address, uint16_t port) {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in where{};
  where.sin_family = AF_INET;
  where.sin_port = htons(port);
  inet_pton(AF_INET, address, &where.sin_addr);
  const int error = bind(fd, reinterpret_cast<const sockaddr*>(&where), sizeof where) == 0 ? 0 : errno;
  close(fd);
  return error;
}

TEST(WorldSubsetTest, AServerOfSomeRobotsServesOnlyTheirCtlAddresses) {
  // MakeScenario: robot i's server address is 127.77.0.(4i+1), on loopback.
  const Scenario scenario = MakeScenario(FourRobots());
  ServerOptions options;
  options.world.robots = {1, 3};
  PhysicsServer server(scenario, options);
  EXPECT_EQ(server.world().robots(), (std::vector<int>{1, 3}));
  const uint16_t port = testing::TestPhysicsPort();
  EXPECT_EQ(BindError("127.77.0.1", port), 0);  // robot 0: another host's
  EXPECT_EQ(BindError("127.77.0.5", port), EADDRINUSE);
  EXPECT_EQ(BindError("127.77.0.9", port), 0);  // robot 2
  EXPECT_EQ(BindError("127.77.0.13", port), EADDRINUSE);
  server.Advance(10);
  EXPECT_EQ(server.world().now_ns(), 10 * kNsPerMs);
}

}  // namespace
}  // namespace sitlnet::physics

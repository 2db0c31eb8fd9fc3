#include "physics_mujoco/test/test_scenarios.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

namespace sitlnet::physics::testing {

uint16_t TestPhysicsPort() { return static_cast<uint16_t>(20000 + 2 * (getpid() % 15000)); }
uint16_t TestJsonPort() { return static_cast<uint16_t>(TestPhysicsPort() + 1); }

Scenario MakeScenario(const std::string& body, const std::string& timing, int physics_step_us) {
  const std::string text =
      "name: \"phys\"\n" + body + "\naddresses { ctl_subnet: \"127.77.0.0/16\" physics_port: " +
      std::to_string(TestPhysicsPort()) +
      " }\n"
      "timing { iteration_us: 10000 physics_step_us: " +
      std::to_string(physics_step_us) + " network_step_us: 10000 " + timing + " }\n";
  return LoadScenarioText(text, "test.textproto");
}

bool WaitReadable(int fd, int timeout_ms) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, timeout_ms) > 0;
}

ServerOptions FrameGate(TimeNs timeout_ns) {
  ServerOptions options;
  options.frame_gate_timeout_ns = timeout_ns;
  return options;
}

namespace {
void ExpectSameVector(const Vec3d& a, const Vec3d& b, const std::string& where) {
  EXPECT_EQ(a.x, b.x) << where;
  EXPECT_EQ(a.y, b.y) << where;
  EXPECT_EQ(a.z, b.z) << where;
}
}  // namespace

void ExpectSamePose(const RobotPose& a, const RobotPose& b, const std::string& where) {
  ExpectSameVector(a.position_m, b.position_m, where + ": position");
  EXPECT_EQ(a.orientation.w, b.orientation.w) << where;
  EXPECT_EQ(a.orientation.x, b.orientation.x) << where;
  EXPECT_EQ(a.orientation.y, b.orientation.y) << where;
  EXPECT_EQ(a.orientation.z, b.orientation.z) << where;
  ExpectSameVector(a.velocity_m_s, b.velocity_m_s, where + ": velocity");
  ExpectSameVector(a.angular_velocity_rad_s, b.angular_velocity_rad_s, where + ": angular velocity");
}

std::vector<int> TakeSilentRobots(PhysicsServer* server) {
  std::vector<int> robots;
  for (const SilentAutopilot& silent : server->TakeSilentAutopilots()) {
    robots.push_back(silent.robot);
  }
  return robots;
}

}  // namespace sitlnet::physics::testing

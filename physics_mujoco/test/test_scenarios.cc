#include "physics_mujoco/test/test_scenarios.h"

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

std::vector<int> TakeSilentRobots(PhysicsServer* server) {
  std::vector<int> robots;
  for (const SilentAutopilot& silent : server->TakeSilentAutopilots()) {
    robots.push_back(silent.robot);
  }
  return robots;
}

}  // namespace sitlnet::physics::testing

// physics_rtt_bench: round trip of MotorCommand -> RobotState over a real ctl0 veth (needs
// root). Brings up a one-robot scenario with nns, runs the physics server in this thread and
// a client (the physics client library) in a thread inside the robot's namespace. The server
// steps once per command (lock-step, state_rate_hz = 1 / step), so a round trip is: command
// through the veth, Poll, one physics step, RobotState back through the veth.
//   physics_rtt_bench [ROUND_TRIPS]   (default 5000; prints median, p90, p99 in us)
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "nns/nns.h"
#include "physics_mujoco/client/physics_client.h"
#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {
namespace {

struct ScenarioUp {
  explicit ScenarioUp(const Scenario& scenario) : name(scenario.name) { nns::Up(scenario); }
  ~ScenarioUp() { nns::Down(name); }
  std::string name;
};

int Run(int round_trips) {
  nns::RequirePrivileges();
  const unsigned pid = static_cast<unsigned>(getpid());
  const std::string third = std::to_string(pid % 250);
  const std::string name = "prtt" + std::to_string(pid % 100000);
  const std::string path = "/tmp/" + name + ".textproto";
  std::ofstream(path) << "name: \"" << name << "\"\n"
                      << "robot { name: \"r1\" position_m { z: 2 } state_rate_hz: 1000 }\n"
                      << "addresses { ctl_subnet: \"10.224." << third
                      << ".0/24\" wlan_subnet: \"10.229." << third << ".0/24\" }\n";
  const Scenario scenario = LoadScenarioFile(path);
  std::remove(path.c_str());
  ScenarioUp up(scenario);
  // Its sockets where runs make them: the scenario's ctl namespace, where ctl0 ends.
  ServerOptions options;
  options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario.name));
  PhysicsServer server(scenario, options);
  const std::string address = FormatIpv4(scenario.robots[0].ctl_root_address) + ":" +
                              std::to_string(scenario.spec.addresses().physics_port());

  std::vector<double> rtt_us;
  std::atomic<bool> done{false};
  std::thread robot([&] {
    std::optional<physics_client::PhysicsClient> client;
    {
      nns::ScopedNetns inside(scenario.robots[0].netns);
      client.emplace(address);
    }
    proto::RobotState state;
    const int warmup = 200;
    for (int i = 1; i <= round_trips + warmup; ++i) {
      const TimeNs start = MonotonicNowNs();
      client->SendRotorSpeeds({800, 800, 800, 800}, i);
      bool got = false;
      while (!got && client->Receive(&state, 1000)) got = state.command_step() == uint64_t(i);
      if (!got) {
        std::fprintf(stderr, "physics_rtt_bench: no state for command %d\n", i);
        break;
      }
      if (i > warmup) rtt_us.push_back(static_cast<double>(MonotonicNowNs() - start) / kNsPerUs);
    }
    done.store(true);
  });
  while (!done.load()) {
    pollfd fd{server.wait_fd(), POLLIN, 0};
    if (poll(&fd, 1, 10) > 0) server.Advance(1);  // Advance polls first
  }
  robot.join();
  if (rtt_us.empty()) return 1;
  std::sort(rtt_us.begin(), rtt_us.end());
  auto at = [&](double q) { return rtt_us[static_cast<size_t>(q * (rtt_us.size() - 1))]; };
  std::printf(
      "command -> state over ctl0, %zu round trips: median %.1f us, p90 %.1f us, "
      "p99 %.1f us, min %.1f us\n",
      rtt_us.size(), at(0.5), at(0.9), at(0.99), rtt_us.front());
  return 0;
}

}  // namespace
}  // namespace sitlnet::physics

int main(int argc, char** argv) {
  try {
    return sitlnet::physics::Run(argc > 1 ? std::atoi(argv[1]) : 5000);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "physics_rtt_bench: %s\n", e.what());
    return 1;
  }
}

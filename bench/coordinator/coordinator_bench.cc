// coordinator_bench: the DANCERS overhead figures (Sec. V-B) for sitlnet.
//
//   coordinator_bench compression   zlib cost vs gain table (threshold choice)
//   coordinator_bench matrix [iterations]
//                                   overhead share and STF for 1/8/32/64 robots,
//                                   Δ=δ=10 ms and Δ=10 ms/δ_net=1 ms, in-process,
//                                   Unix socket and TCP loopback
//   coordinator_bench run TRANSPORT ROBOTS NET_STEP_US ITERATIONS
//   coordinator_bench serve ROLE ENDPOINT ROBOTS NET_STEP_US   (a connector process)
//
// Network side: the real medium (mac_phy_sim), every robot broadcasting 200 B
// at 10 Hz (the broadcast scale workload of docs/references.md#ns3-tapbridge), all robots in range.
// Physics side: the real MuJoCo world (physics_mujoco's World, 2 threads,
// δ_phy = 1 ms, every robot hovering), or with SITLNET_BENCH_PHYSICS=synthetic
// a measured busy loop of kPhysicsWorkNsPerRobotStep per robot per step
// (MuJoCo's cost from docs/references.md#mujoco); tables say which.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "coordinator/coordinator.h"
#include "coordinator/synthetic.h"
#include "network_side/network_side.h"
#include "physics_side/physics_side.h"

namespace sitlnet::coordinator {

using namespace network_side;  // NOLINT(google-build-using-namespace)
using namespace physics_side;  // NOLINT(google-build-using-namespace)

int RunCompressionBench();

namespace {

// docs/references.md#mujoco: 64 quadrotors, separate mjData on one mjModel, 2 threads:
// 43 µs per physics step -> 672 ns per robot per step (wall).
constexpr TimeNs kPhysicsWorkNsPerRobotStep = 672;
constexpr TimeNs kBroadcastPeriodNs = 100 * kNsPerMs;  // 10 Hz
constexpr int kBroadcastBytes = 200;

// Receive spin (Channel::set_spin_ns) from env SITLNET_SPIN_US, default 0.
TimeNs SpinNs() {
  const char* text = std::getenv("SITLNET_SPIN_US");
  return text ? std::atoll(text) * kNsPerUs : 0;
}

Scenario BenchScenario(int robots, TimeNs net_step_us) {
  std::string text = "name: \"bench\"\n";
  for (int i = 0; i < robots; ++i) {
    // An 8-wide grid, 5 m apart: every robot hears every other one.
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(5 * (i % 8)) +
            " y: " + std::to_string(5 * (i / 8)) + " z: 10 } }\n";
  }
  text += "radio { standard: STANDARD_80211A rate_mbps: 54 }\n";
  text += "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: " +
          std::to_string(net_step_us) + " duration_ms: 1000000 pacing: PACING_LOCKSTEP }\n";
  return LoadScenarioText(text, "bench.textproto");
}

SyntheticOptions PhysicsWork(const Scenario& s) {
  SyntheticOptions options;
  options.robots = static_cast<int>(s.robots.size());
  options.step_ns = s.physics_step_ns;
  options.work_per_step_ns = kPhysicsWorkNsPerRobotStep * options.robots;
  return options;
}

bool SyntheticPhysicsChosen() {
  const char* text = std::getenv("SITLNET_BENCH_PHYSICS");
  return text && std::string(text) == "synthetic";
}

// Hover: thrust of four rotors equals weight.
void Hover(physics::World* world) {
  for (int i = 0; i < world->robot_count(); ++i) {
    const proto::Airframe& a = world->airframe(i);
    const double w = std::sqrt(a.mass_kg() * 9.81 / (4 * a.thrust_coefficient()));
    world->SetRotorSpeeds(i, {w, w, w, w});
  }
}

// The physics simulator of the bench: MuJoCo or synthetic.
struct BenchPhysics {
  explicit BenchPhysics(const Scenario& scenario) {
    if (SyntheticPhysicsChosen()) {
      synthetic = std::make_unique<SyntheticPhysics>(PhysicsWork(scenario));
    } else {
      world = std::make_unique<physics::World>(scenario);
      Hover(world.get());
      mujoco = std::make_unique<WorldSimulator>(scenario, world.get());
    }
  }
  Simulator* get() { return synthetic ? static_cast<Simulator*>(synthetic.get()) : mujoco.get(); }
  std::unique_ptr<SyntheticPhysics> synthetic;
  std::unique_ptr<physics::World> world;
  std::unique_ptr<WorldSimulator> mujoco;
};

// The shared secret of the "-auth" transports: every message after the handshake is tagged.
const char kBenchSecret[] = "coordinator_bench secret, 32 B!";

int Serve(const std::string& role, const std::string& endpoint, int robots, int net_step_us,
          bool authenticate) {
  const Scenario scenario = BenchScenario(robots, net_step_us);
  const ConnectorIdentity identity{role, role == "physics" ? Role::kPhysics : Role::kNetwork,
                                   ScenarioHash(scenario),
                                   authenticate ? kBenchSecret : std::string()};
  Channel channel(Connect(ParseEndpoint(endpoint), MonotonicNowNs() + 10 * kNsPerS));
  channel.set_spin_ns(SpinNs());
  if (identity.role == Role::kPhysics) {
    BenchPhysics physics(scenario);
    ServeCoordinator(channel, *physics.get(), identity, 10 * kNsPerS);
  } else {
    PeriodicBroadcast traffic(robots, kBroadcastPeriodNs, kBroadcastBytes);
    MediumSimulator medium(scenario, &traffic);
    ServeCoordinator(channel, medium, identity, 10 * kNsPerS);
  }
  return 0;
}

struct Row {
  std::string transport;
  int robots = 0;
  int net_step_us = 0;
  MetricsSummary summary;
};

Row RunOne(const std::string& labelled_transport, int robots, int net_step_us, int64_t iterations) {
  // "<transport>-auth": the same with a shared secret (docs/coordinator.md, "Authentication").
  const bool authenticate = labelled_transport.ends_with("-auth");
  const std::string transport = authenticate
                                    ? labelled_transport.substr(0, labelled_transport.size() - 5)
                                    : labelled_transport;
  const Scenario scenario = BenchScenario(robots, net_step_us);
  CoordinatorOptions options = OptionsFromScenario(scenario);
  options.iterations = iterations;
  MetricsCollector metrics;
  options.metrics = &metrics;
  if (transport == "inproc") {
    BenchPhysics physics_sim(scenario);
    PeriodicBroadcast traffic(robots, kBroadcastPeriodNs, kBroadcastBytes);
    MediumSimulator medium(scenario, &traffic);
    // The slower side (physics here, as the T_phy and T_net columns show)
    // runs on the coordinator's thread: the coordinator then never sleeps
    // waiting for it, and the faster side has finished when it looks.
    const bool physics_slower = true;
    auto physics =
        MakeInProcessConnector("physics", Role::kPhysics, physics_sim.get(),
                               physics_slower ? Threading::kCallerThread : Threading::kOwnThread);
    auto network = MakeInProcessConnector(
        "network", Role::kNetwork, &medium,
        physics_slower ? Threading::kOwnThread : Threading::kCallerThread, SpinNs());
    RunCoordinator(*physics, *network, options);
  } else {
    // "uds"/"tcp": both connectors in their own processes. "uds-net"/"tcp-net":
    // physics (the slower side) in the coordinator's process on its thread,
    // only the network connector remote -- the layout for a remote medium.
    const bool hybrid = transport.ends_with("-net");
    const std::string where = transport.starts_with("uds")
                                  ? "unix:/tmp/sitlnet-bench-" + std::to_string(getpid()) + ".sock"
                                  : "127.0.0.1:0";
    Listener listener(ParseEndpoint(where));
    const std::string endpoint = listener.endpoint().ToString();
    std::vector<pid_t> children;
    for (const char* role : {"physics", "network"}) {
      if (hybrid && std::string(role) == "physics") continue;
      const pid_t pid = fork();
      if (pid == 0) {
        const std::string r = std::to_string(robots), s = std::to_string(net_step_us);
        execl("/proc/self/exe", "coordinator_bench", "serve", role, endpoint.c_str(), r.c_str(),
              s.c_str(), authenticate ? "auth" : "plain", static_cast<char*>(nullptr));
        _exit(127);
      }
      children.push_back(pid);
    }
    WaitLimits limits;
    limits.timeout_ns = 10 * kNsPerS;
    limits.deadline_ns = MonotonicNowNs() + limits.timeout_ns;
    HandshakeExpectation expect{ScenarioHash(scenario), scenario.iteration_ns, false, std::nullopt,
                                authenticate ? kBenchSecret : std::string()};
    if (hybrid) {
      BenchPhysics physics_sim(scenario);
      auto physics = MakeInProcessConnector("physics", Role::kPhysics, physics_sim.get(),
                                            Threading::kCallerThread);
      Channel channel(listener.Accept(limits.deadline_ns));
      channel.set_spin_ns(SpinNs());
      auto network = AcceptConnector(std::move(channel), expect, limits);
      RunCoordinator(*physics, *network, options);
    } else {
      AcceptedConnectors c = AcceptConnectors(listener, expect, limits, {}, SpinNs());
      RunCoordinator(*c.physics, *c.network, options);
    }
    for (pid_t pid : children) waitpid(pid, nullptr, 0);
  }
  return {labelled_transport, robots, net_step_us, metrics.Summarize()};
}

std::string TransportLabel(const std::string& t) {
  if (t == "inproc") return "in-process";
  if (t == "uds") return "Unix socket";
  if (t == "tcp") return "TCP loopback";
  if (t == "uds-net") return "physics in-process, network over Unix socket";
  if (t == "tcp-net") return "physics in-process, network over TCP loopback";
  if (t == "tcp-net-auth") return "physics in-process, network over TCP loopback, tagged";
  return t;
}

void PrintHeader() {
  std::printf(
      "| transport | robots | Δ / δ_net | T_phy µs (%s) | T_net µs (medium) | "
      "T_total µs | T_overhead µs mean | p99 | overhead share | STF |\n",
      SyntheticPhysicsChosen() ? "synthetic" : "MuJoCo");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
}

void PrintRow(const Row& r) {
  const MetricsSummary& s = r.summary;
  std::printf("| %s | %d | 10 / %g ms | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f %% | %.4f |\n",
              TransportLabel(r.transport).c_str(), r.robots, r.net_step_us / 1000.0,
              1e3 * s.t_phy_ms.mean, 1e3 * s.t_net_ms.mean, 1e3 * s.t_total_ms.mean,
              1e3 * s.t_overhead_ms.mean, 1e3 * s.t_overhead_ms.p99, 100 * s.overhead_share,
              s.stf.mean);
  std::fflush(stdout);
}

int Main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "serve" && argc == 7) {
    return Serve(argv[2], argv[3], std::atoi(argv[4]), std::atoi(argv[5]),
                 std::string(argv[6]) == "auth");
  }
  if (command == "compression") return RunCompressionBench();
  if (command == "run" && argc == 6) {
    PrintHeader();
    PrintRow(RunOne(argv[2], std::atoi(argv[3]), std::atoi(argv[4]), std::atoll(argv[5])));
    return 0;
  }
  if (command == "matrix") {
    const int64_t iterations = argc > 2 ? std::atoll(argv[2]) : 1000;
    PrintHeader();
    for (int net_step_us : {10000, 1000}) {
      for (int robots : {1, 8, 32, 64}) {
        for (const char* transport : {"inproc", "uds", "tcp", "uds-net", "tcp-net"}) {
          PrintRow(RunOne(transport, robots, net_step_us, iterations));
        }
      }
    }
    return 0;
  }
  std::fprintf(stderr,
               "usage: coordinator_bench compression | matrix [iterations] | run "
               "inproc|uds|tcp|uds-net|tcp-net[-auth] ROBOTS NET_STEP_US ITERATIONS\n");
  return 2;
}

}  // namespace
}  // namespace sitlnet::coordinator

int main(int argc, char** argv) {
  try {
    return sitlnet::coordinator::Main(argc, argv);
  } catch (const sitlnet::Error& e) {
    std::fprintf(stderr, "coordinator_bench: %s\n", e.what());
    return 1;
  }
}

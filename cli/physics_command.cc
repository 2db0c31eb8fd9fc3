// `sitlnet physics SCENARIO`: the MuJoCo physics server of a scenario in standalone realtime
// mode (docs/physics.md): robots fly by sending MotorCommand over their ctl0.
#include <sys/stat.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/options.h"
#include "nns/nns.h"
#include "physics_mujoco/physics_mujoco.h"
#include "scenario/scenario.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kPhysicsFooter =
    "Runs the MuJoCo physics of SCENARIO (a scenario file, or the name of a scenario\n"
    "that is up) in real time (the scenario's realtime_factor), one physics step at a\n"
    "time, until SIGINT/SIGTERM or S seconds of virtual time. Each robot's server\n"
    "listens on <root side of its ctl0>:<physics_port> (SITLNET_PHYSICS_ADDR inside\n"
    "the robot; protocol in docs/protocols.md) and, if the robot sets\n"
    "ardupilot_json_port, speaks ArduPilot's JSON SITL protocol there. When the\n"
    "scenario is up, the sockets are in its ctl namespace (<scenario>.ctl; needs\n"
    "CAP_SYS_ADMIN); before `up`, in this process's namespace, where robots do not\n"
    "reach them. `sitlnet down` of the scenario stops it too.\n"
    "Prints per-robot counters at exit.\n"
    "\n"
    "exit codes: 0 ok, 1 failed, 2 usage or bad scenario file.";

void PrintCounters(const Scenario& scenario, const physics::PhysicsServer& server) {
  std::printf("%-12s %9s %9s %9s %9s %9s %9s %7s %9s\n", "robot", "commands", "states", "malformed",
              "invalid", "wrong_id", "foreign", "cuts", "json");
  for (const RobotPlan& robot : scenario.robots) {
    const physics::RobotCounters& c = server.counters(robot.index);
    std::printf("%-12s %9lu %9lu %9lu %9lu %9lu %9lu %7lu %9lu\n", robot.name.c_str(),
                c.commands_accepted, c.states_sent, c.dropped_malformed, c.dropped_invalid,
                c.dropped_wrong_robot, c.dropped_foreign_source, c.failsafe_cuts, c.json_frames);
  }
}

int Physics(const std::string& scenario_arg, double duration_s, physics::ServerOptions options) {
  Scenario scenario;
  const int load_status = ReportErrors("physics", kExitUsage, [&] {
    scenario = LoadByFileOrName(scenario_arg);
    return kExitOk;
  });
  if (load_status != kExitOk) return load_status;
  return ReportErrors("physics", kExitFailure, [&] {
    // When the scenario is up, its sockets are made in the scenario's ctl namespace, where the
    // robots' ctl0 links end (entering it needs CAP_SYS_ADMIN), and `sitlnet down` stops this
    // server too. Before `up` they are in this process's namespace (IP_FREEBIND), where no
    // robot reaches them: a server for tests of the protocol.
    const bool up =
        nns::ReadScenarioState(scenario.name) && nns::NetnsExists(nns::CtlNetnsName(scenario.name));
    if (up) options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario.name));
    physics::PhysicsServer server(scenario, options);
    std::optional<nns::DaemonRegistration> registration;
    if (up) registration.emplace(scenario.name, "physics");
    StopSignal stop;
    std::fprintf(stderr, "sitlnet physics: %zu robots, step %ld us, serving on port %u\n",
                 scenario.robots.size(), static_cast<long>(scenario.physics_step_ns / kNsPerUs),
                 scenario.spec.addresses().physics_port());
    const TimeNs max_lag_ns =
        physics::RunRealtime(&server, scenario.spec.timing().realtime_factor(),
                             static_cast<TimeNs>(duration_s * kNsPerS), stop.fd());
    std::fprintf(stderr, "sitlnet physics: stopped at %.3f s virtual time, max lag %.3f ms\n",
                 static_cast<double>(server.world().time_ns(0)) / kNsPerS,
                 static_cast<double>(max_lag_ns) / kNsPerMs);
    PrintCounters(scenario, server);
    return kExitOk;
  });
}

}  // namespace

Command AddPhysicsCommand(CLI::App& sitlnet) {
  CLI::App* command =
      sitlnet.add_subcommand("physics", "run a scenario's MuJoCo physics in real time");
  command->footer(kPhysicsFooter);
  struct Arguments {
    std::string scenario;
    double duration_s = 0;  // 0: until a signal.
    physics::ServerOptions options;
  };
  auto arguments = std::make_shared<Arguments>();
  AddScenarioFileOrName(*command, &arguments->scenario);
  // At most a year, as a scenario's duration: the nanoseconds stay far from int64's end.
  command
      ->add_option("--duration-s", arguments->duration_s,
                   "stop after S seconds of virtual time, at most a year (default: never)")
      ->type_name("S")
      ->check(SecondsIn(0, true, static_cast<double>(kMaxDurationMs / 1000)));
  command->add_option("--threads", arguments->options.world.threads, "threads stepping robots")
      ->type_name("N")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()).description("at least 1"))
      ->capture_default_str();
  command->add_flag_function(
      "--euler",
      [arguments](int64_t) { arguments->options.world.integrator = physics::Integrator::kEuler; },
      "semi-implicit Euler, whatever the scenario says (docs/physics.md)");
  return {command, [arguments] {
            return Physics(arguments->scenario, arguments->duration_s, arguments->options);
          }};
}

}  // namespace sitlnet::cli

// `sitlnet medium SCENARIO [--pcap FILE]`: the medium daemon of a scenario
// that is up (docs/tapbridge.md).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/options.h"
#include "nns/nns.h"
#include "runner/runner.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kMediumFooter =
    "Two forms:\n"
    "  sitlnet medium SCENARIO [--pcap FILE] [--stats-interval-ms N] [--rt-priority P]\n"
    "                          [--spin-us N] [--relay]\n"
    "  sitlnet medium SCENARIO --connect HOST:PORT [--seed N] [--no-shadowing]\n"
    "                          [--connect-timeout S] [--secret-file PATH]\n"
    "\n"
    "Runs the simulated 802.11 medium between the robots of SCENARIO (a scenario\n"
    "file, or the name of a scenario that is up): attaches every robot's wlan0,\n"
    "delivers frames when and if the medium says, in real time (the scenario's\n"
    "realtime_factor), until SIGINT or SIGTERM. The scenario must be up\n"
    "(sitlnet up FILE). Logs delivery lateness every stats interval (default\n"
    "5000 ms) and per-robot counters at exit. `sitlnet down` stops it too.\n"
    "Control socket: /run/sitlnet/<scenario>/medium.sock (positions, counters,\n"
    "live pcap: sitlnet capture --medium).\n"
    "\n"
    "With --connect, no TAPs and no privileges: this host runs only the 802.11\n"
    "model, for `sitlnet run SCENARIO --listen HOST:PORT --remote network` on the\n"
    "robots' host (docs/coordinator.md, \"A connector on another host\"). It\n"
    "connects to HOST:PORT (retrying while nothing listens, up to\n"
    "--connect-timeout S, default 60), proves with the scenario's hash that it\n"
    "loaded the same SCENARIO file (give the run's --seed and --no-shadowing\n"
    "too), serves every network step until the run ends, and exits 0; the\n"
    "pcap and counters are written in the run folder on the robots' host.\n"
    "\n"
    "exit codes: 0 stopped by a signal (--connect: the run ended), 1 failed\n"
    "(scenario not up, daemon already running; --connect: coordinator\n"
    "unreachable, refused the handshake, or vanished mid-run), 2 usage or bad\n"
    "scenario file, 3 missing privileges.";

struct MediumArguments {
  std::string scenario;
  tapbridge::DaemonOptions daemon;
  std::string connect;  // Empty: the local daemon.
  std::optional<uint64_t> seed;
  bool no_shadowing = false;
  TimeNs connect_timeout_ns = 60 * kNsPerS;
  std::string secret_file;
};

int Medium(const MediumArguments& arguments) {
  const std::string& scenario_arg = arguments.scenario;
  const std::string& connect = arguments.connect;
  Scenario scenario;
  const int load_status = ReportErrors("medium", kExitUsage, [&] {
    scenario = LoadByFileOrName(scenario_arg);
    return kExitOk;
  });
  if (load_status != kExitOk) return load_status;
  if (!connect.empty()) {
    return ReportErrors("medium", kExitFailure, [&] {
      runner::RunOptions overrides;  // As `sitlnet run` applies them: both hash the same scenario.
      overrides.seed = arguments.seed;
      overrides.no_shadowing = arguments.no_shadowing;
      network_side::RemoteMediumOptions remote;
      remote.coordinator_endpoint = connect;
      remote.connect_timeout_ns = arguments.connect_timeout_ns;
      remote.secret_file = arguments.secret_file;
      const std::string reason =
          network_side::ServeRemoteMedium(runner::ApplyRunOverrides(scenario, overrides), remote);
      std::fprintf(stderr, "sitlnet medium: %s: stopped: %s\n", scenario.name.c_str(),
                   reason.c_str());
      return kExitOk;
    });
  }
  return ReportErrors("medium", kExitFailure, [&] {
    nns::RequirePrivileges();
    nns::DaemonRegistration registration(scenario.name, "medium");  // `down` stops us too
    return tapbridge::RunMediumDaemon(scenario, arguments.daemon);
  });
}

}  // namespace

Command AddMediumCommand(CLI::App& sitlnet) {
  CLI::App* medium =
      sitlnet.add_subcommand("medium", "run the simulated 802.11 medium of a scenario");
  medium->footer(kMediumFooter);
  auto arguments = std::make_shared<MediumArguments>();
  tapbridge::DaemonOptions& daemon = arguments->daemon;
  AddScenarioFileOrName(*medium, &arguments->scenario);
  // The local daemon's options.
  CLI::Option* pcap =
      medium
          ->add_option("--pcap", daemon.pcap_path,
                       "write every frame on the air as 802.11 + radiotap (tshark -r FILE)")
          ->type_name("FILE");
  CLI::Option* stats = medium
                           ->add_option_function<int64_t>(
                               "--stats-interval-ms",
                               [&daemon](int64_t ms) { daemon.stats_interval_ns = ms * kNsPerMs; },
                               "period of the delivery-lateness log (default 5000)")
                           ->type_name("N");
  CLI::Option* spin =
      medium
          ->add_option_function<int64_t>(
              "--spin-us", [&daemon](int64_t us) { daemon.spin_ns = us * kNsPerUs; },
              "wake N us before each event and busy-wait (precision for CPU; default 0)")
          ->type_name("N");
  CLI::Option* priority = AddRtPriorityOption(*medium, &daemon.realtime_priority);
  CLI::Option* relay = medium->add_flag("--relay", daemon.use_relay_medium,
                                        "no 802.11 model: relay frames at once (benchmark floor)");
  // The remote medium's options.
  CLI::Option* connect =
      medium
          ->add_option("--connect", arguments->connect,
                       "serve the 802.11 model to `sitlnet run SCENARIO --listen HOST:PORT "
                       "--remote network` on the robots' host (below)")
          ->type_name("HOST:PORT");
  for (CLI::Option* local : {pcap, stats, spin, priority, relay}) connect->excludes(local);
  AddSeedOption(*medium, &arguments->seed)->needs(connect);
  AddNoShadowingOption(*medium, &arguments->no_shadowing)->needs(connect);
  AddSecretFileOption(*medium, &arguments->secret_file)->needs(connect);
  AddPeerTimeoutOption(*medium, "--connect-timeout",
                       "longest wait for the run to listen, retrying meanwhile",
                       &arguments->connect_timeout_ns);
  return {medium, [arguments] { return Medium(*arguments); }};
}

}  // namespace sitlnet::cli

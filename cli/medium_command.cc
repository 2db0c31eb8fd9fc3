// `sitlnet medium SCENARIO [--pcap FILE]`: the medium daemon of a scenario
// that is up (docs/tapbridge.md).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "nns/nns.h"
#include "runner/runner.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kMediumHelp =
    "usage: sitlnet medium SCENARIO [--pcap FILE] [--stats-interval-ms N] [--rt-priority P]\n"
    "                              [--spin-us N] [--relay]\n"
    "       sitlnet medium SCENARIO --connect HOST:PORT [--seed N] [--no-shadowing]\n"
    "                              [--connect-timeout S] [--secret-file PATH]\n"
    "\n"
    "Runs the simulated 802.11 medium between the robots of SCENARIO (a scenario\n"
    "file, or the name of a scenario that is up): attaches every robot's wlan0,\n"
    "delivers frames when and if the medium says, in real time (the scenario's\n"
    "realtime_factor), until SIGINT or SIGTERM. The scenario must be up\n"
    "(sitlnet up FILE). Logs delivery lateness every stats interval (default\n"
    "5000 ms) and per-robot counters at exit.\n"
    "\n"
    "  --pcap FILE   write every frame on the air as 802.11 + radiotap (tshark -r FILE)\n"
    "  --rt-priority P  SCHED_FIFO priority (default 10; 0: normal scheduling)\n"
    "  --spin-us N   wake N us before each event and busy-wait (precision for CPU; default 0)\n"
    "  --relay       no 802.11 model: relay frames at once (benchmark floor)\n"
    "\n"
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
    "--secret-file PATH: the shared secret both ends prove they hold (the same\n"
    "file as the run's --secret-file; owner-only, 16 to 4096 bytes; needed when\n"
    "the run listens on an address other hosts can reach; docs/coordinator.md,\n"
    "\"Authentication\").\n"
    "\n"
    "exit codes: 0 stopped by a signal (--connect: the run ended), 1 failed\n"
    "(scenario not up, daemon already running; --connect: coordinator\n"
    "unreachable, refused the handshake, or vanished mid-run), 2 usage or bad\n"
    "scenario file, 3 missing privileges.\n";

}  // namespace

int RunMediumCommand(int argc, char** argv) {
  if (WantsHelp(argc, argv)) {
    std::fputs(kMediumHelp, stdout);
    return kExitOk;
  }
  std::string scenario_arg;
  tapbridge::DaemonOptions options;
  std::string connect;
  std::optional<uint64_t> seed;
  bool no_shadowing = false;
  bool daemon_option = false;  // One that only the local daemon uses.
  TimeNs connect_timeout_ns = 60 * kNsPerS;
  std::string secret_file;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto number = [&](const std::string& text) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !(value >= 0)) {
        std::fprintf(stderr, "sitlnet medium: %s \"%s\" is not a number\n", arg.c_str(),
                     text.c_str());
        std::exit(kExitUsage);
      }
      return value;
    };
    daemon_option = daemon_option || arg == "--pcap" || arg == "--stats-interval-ms" ||
                    arg == "--spin-us" || arg == "--rt-priority" || arg == "--relay";
    if (arg == "--connect" && i + 1 < argc) {
      connect = argv[++i];
    } else if (arg == "--seed" && i + 1 < argc) {
      const std::string text = argv[++i];
      char* end = nullptr;
      seed = std::strtoull(text.c_str(), &end, 10);
      if (end == text.c_str() || *end != '\0') {
        std::fprintf(stderr, "sitlnet medium: --seed \"%s\" is not a number\n", text.c_str());
        return kExitUsage;
      }
    } else if (arg == "--no-shadowing") {
      no_shadowing = true;
    } else if (arg == "--secret-file" && i + 1 < argc) {
      secret_file = argv[++i];
    } else if (arg == "--connect-timeout" && i + 1 < argc) {
      const double seconds = number(argv[++i]);
      // Bounded: seconds x 1e9 must fit the int64 nanoseconds added to the clock.
      if (!(seconds > 0 && seconds <= 86400)) {
        std::fprintf(stderr,
                     "sitlnet medium: --connect-timeout \"%s\" is not 0 < S <= 86400 seconds\n",
                     argv[i]);
        return kExitUsage;
      }
      connect_timeout_ns = static_cast<TimeNs>(seconds * kNsPerS);
    } else if (arg == "--pcap" && i + 1 < argc) {
      options.pcap_path = argv[++i];
    } else if (arg == "--stats-interval-ms" && i + 1 < argc) {
      options.stats_interval_ns = std::stoll(argv[++i]) * kNsPerMs;
    } else if (arg == "--spin-us" && i + 1 < argc) {
      options.spin_ns = std::stoll(argv[++i]) * kNsPerUs;
    } else if (arg == "--rt-priority" && i + 1 < argc) {
      options.realtime_priority = std::stoi(argv[++i]);
    } else if (arg == "--relay") {
      options.use_relay_medium = true;
    } else if (scenario_arg.empty() && !arg.starts_with("-")) {
      scenario_arg = arg;
    } else {
      std::fprintf(stderr, "sitlnet medium: unexpected argument \"%s\"\n%s", arg.c_str(),
                   kMediumHelp);
      return kExitUsage;
    }
  }
  if (scenario_arg.empty()) {
    std::fputs(kMediumHelp, stderr);
    return kExitUsage;
  }
  if (connect.empty() ? (seed || no_shadowing || !secret_file.empty()) : daemon_option) {
    std::fprintf(stderr,
                 connect.empty()
                     ? "sitlnet medium: --seed, --no-shadowing and --secret-file go with --connect "
                       "(the local daemon uses the scenario's)\n"
                     : "sitlnet medium: --connect takes only --seed, --no-shadowing, "
                       "--connect-timeout and --secret-file (the pcap is written by the run)\n");
    return kExitUsage;
  }
  Scenario scenario;
  const int load_status = ReportErrors("medium", kExitUsage, [&] {
    scenario = LoadByFileOrName(scenario_arg);
    return kExitOk;
  });
  if (load_status != kExitOk) return load_status;
  if (!connect.empty()) {
    return ReportErrors("medium", kExitFailure, [&] {
      runner::RunOptions overrides;  // As `sitlnet run` applies them: both hash the same scenario.
      overrides.seed = seed;
      overrides.no_shadowing = no_shadowing;
      network_side::RemoteMediumOptions remote;
      remote.coordinator_endpoint = connect;
      remote.connect_timeout_ns = connect_timeout_ns;
      remote.secret_file = secret_file;
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
    return tapbridge::RunMediumDaemon(scenario, options);
  });
}

}  // namespace sitlnet::cli

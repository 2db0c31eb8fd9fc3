// `sitlnet medium SCENARIO [--pcap FILE]`: the medium daemon of a scenario
// that is up (docs/tapbridge.md).
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "cli/commands.h"
#include "nns/nns.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kMediumHelp =
    "usage: sitlnet medium SCENARIO [--pcap FILE] [--stats-interval-ms N] [--rt-priority P]\n"
    "                              [--spin-us N] [--relay]\n"
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
    "exit codes: 0 stopped by a signal, 1 failed (scenario not up, daemon already\n"
    "running), 2 usage or bad scenario file, 3 missing privileges.\n";

}  // namespace

int RunMediumCommand(int argc, char** argv) {
  if (WantsHelp(argc, argv)) {
    std::fputs(kMediumHelp, stdout);
    return kExitOk;
  }
  std::string scenario_arg;
  tapbridge::DaemonOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--pcap" && i + 1 < argc) {
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
  Scenario scenario;
  const int load_status = ReportErrors("medium", kExitUsage, [&] {
    scenario = LoadByFileOrName(scenario_arg);
    return kExitOk;
  });
  if (load_status != kExitOk) return load_status;
  return ReportErrors("medium", kExitFailure, [&] {
    nns::RequirePrivileges();
    nns::DaemonRegistration registration(scenario.name, "medium");  // `down` stops us too
    return tapbridge::RunMediumDaemon(scenario, options);
  });
}

}  // namespace sitlnet::cli

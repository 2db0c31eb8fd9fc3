// `sitlnet run SCENARIO ...`: the whole pipeline (runner/runner.h).
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "cli/commands.h"
#include "runner/runner.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kRunHelp =
    "usage: sitlnet run SCENARIO [--out DIR] [--duration S] [--pacing realtime|lockstep]\n"
    "                   [--seed N] [--no-shadowing] [--no-progress] [--rt-priority P]\n"
    "                   [--listen HOST:PORT --remote network [--remote-timeout S]\n"
    "                    [--secret-file PATH]]\n"
    "\n"
    "Brings SCENARIO up, starts the simulated 802.11 medium, the MuJoCo physics,\n"
    "every robot's image and the coordinator, runs for the scenario's duration\n"
    "(or --duration seconds of simulated time), writes the run folder (default\n"
    "runs/<scenario>-<UTC time>: scenario, trajectories.csv, metrics.csv,\n"
    "medium.pcap, deliveries.csv, connectivity.csv, robots/<name>.log,\n"
    "summary.json, PNG plots) and tears everything down. Ctrl-C stops in order.\n"
    "Images are looked up in $SITLNET_IMAGES, else the source tree's robot_images/.\n"
    "In realtime pacing sitlnet's own threads ask for SCHED_FIFO priority P\n"
    "(--rt-priority, default 10; 0: normal scheduling; without CAP_SYS_NICE a\n"
    "warning, then normal); the images run at normal priority.\n"
    "Each image runs in a sandbox of its own (bubblewrap: own PID and mount\n"
    "namespaces, host files read-only, no capabilities; manifest `sandbox: NONE`\n"
    "to opt out) and, in realtime pacing at a realtime factor other than 1, in\n"
    "dilated time (libfaketime; manifest `time: WALL` to opt out); timing's\n"
    "ros2_clock_hz puts the simulation's time on ROS 2's /clock in every robot\n"
    "(docs/security.md, docs/time.md).\n"
    "\n"
    "  --listen HOST:PORT --remote network\n"
    "      the 802.11 medium model runs on another host: listen on HOST:PORT\n"
    "      (0.0.0.0:7100; port 0 picks one, printed; or unix:/path), wait for\n"
    "      `sitlnet medium SCENARIO --connect THIS_HOST:PORT` there (same scenario\n"
    "      file, same --seed and --no-shadowing), then run; the robots' TAPs and\n"
    "      physics stay here. Lockstep pacing only.\n"
    "  --secret-file PATH  the shared secret both ends prove they hold before\n"
    "      anything else (the same file as `sitlnet medium --connect`'s; owner-only,\n"
    "      16 to 4096 bytes: head -c 32 /dev/urandom > PATH; chmod 600 PATH);\n"
    "      required unless --listen is a loopback address or unix:. It does not\n"
    "      encrypt: on an untrusted network, add an SSH tunnel (docs/coordinator.md).\n"
    "  --remote-timeout S  longest wait for it to connect (default 60)\n"
    "\n"
    "exit codes: 0 ok, 1 failure (a robot failed with on_robot_failure STOP, a\n"
    "component failed), 2 usage or bad scenario, 3 missing privileges,\n"
    "130 interrupted (outputs written so far are complete).\n";

std::string SelfExe() {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return "sitlnet";
  path[n] = '\0';
  return path;
}

}  // namespace

int RunRunCommand(int argc, char** argv) {
  if (WantsHelp(argc, argv)) {
    std::fputs(kRunHelp, stdout);
    return kExitOk;
  }
  runner::RunOptions options;
  std::string remote;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "sitlnet run: %s needs a value\n", arg.c_str());
        std::exit(kExitUsage);
      }
      return argv[++i];
    };
    if (arg == "--out") {
      options.out_dir = value();
    } else if (arg == "--duration") {
      const std::string text = value();
      char* end = nullptr;
      options.duration_s = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !(*options.duration_s > 0) ||
          *options.duration_s > kMaxDurationMs / 1000) {
        std::fprintf(stderr,
                     "sitlnet run: --duration \"%s\" is not a number of seconds in (0, %lld] (a "
                     "year)\n",
                     text.c_str(), static_cast<long long>(kMaxDurationMs / 1000));
        return kExitUsage;
      }
    } else if (arg == "--pacing") {
      const std::string pacing = value();
      if (pacing != "realtime" && pacing != "lockstep") {
        std::fprintf(stderr, "sitlnet run: --pacing must be realtime or lockstep, not \"%s\"\n",
                     pacing.c_str());
        return kExitUsage;
      }
      options.lockstep = pacing == "lockstep";
    } else if (arg == "--seed") {
      const std::string text = value();
      char* end = nullptr;
      options.seed = std::strtoull(text.c_str(), &end, 10);
      if (end == text.c_str() || *end != '\0') {
        std::fprintf(stderr, "sitlnet run: --seed \"%s\" is not a number\n", text.c_str());
        return kExitUsage;
      }
    } else if (arg == "--no-shadowing") {
      options.no_shadowing = true;
    } else if (arg == "--no-progress") {
      options.progress = false;
    } else if (arg == "--rt-priority") {
      const std::string text = value();
      char* end = nullptr;
      const long priority = std::strtol(text.c_str(), &end, 10);
      if (end == text.c_str() || *end != '\0' || priority < 0 || priority > 99) {
        std::fprintf(stderr, "sitlnet run: --rt-priority \"%s\" is not 0..99\n", text.c_str());
        return kExitUsage;
      }
      options.realtime_priority = static_cast<int>(priority);
    } else if (arg == "--listen") {
      options.listen = value();
    } else if (arg == "--secret-file") {
      options.secret_file = value();
    } else if (arg == "--remote") {
      remote = value();
      if (remote != "network") {
        std::fprintf(stderr,
                     "sitlnet run: --remote network is the side that can run on another host, "
                     "not \"%s\" (physics serves the robots' ctl0 here; docs/coordinator.md)\n",
                     remote.c_str());
        return kExitUsage;
      }
    } else if (arg == "--remote-timeout") {
      const std::string text = value();
      char* end = nullptr;
      const double seconds = std::strtod(text.c_str(), &end);
      // Bounded: seconds x 1e9 must fit the int64 nanoseconds added to the clock.
      if (end == text.c_str() || *end != '\0' || !(seconds > 0 && seconds <= 86400)) {
        std::fprintf(stderr, "sitlnet run: --remote-timeout \"%s\" is not 0 < S <= 86400 seconds\n",
                     text.c_str());
        return kExitUsage;
      }
      options.remote_wait_ns = static_cast<TimeNs>(seconds * kNsPerS);
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr, "sitlnet run: unknown option %s\n%s", arg.c_str(), kRunHelp);
      return kExitUsage;
    } else if (options.scenario_path.empty()) {
      options.scenario_path = arg;
    } else {
      std::fprintf(stderr, "sitlnet run: one scenario only (got %s)\n", arg.c_str());
      return kExitUsage;
    }
  }
  if (options.scenario_path.empty()) {
    std::fputs(kRunHelp, stderr);
    return kExitUsage;
  }
  if (options.listen.empty() != remote.empty()) {
    std::fprintf(stderr, "sitlnet run: --listen and --remote network go together\n");
    return kExitUsage;
  }
  if (!options.secret_file.empty() && options.listen.empty()) {
    std::fprintf(stderr, "sitlnet run: --secret-file goes with --listen\n");
    return kExitUsage;
  }
  options.sitlnet_exe = SelfExe();
  const char* images = std::getenv("SITLNET_IMAGES");
  options.images_root = images ? images : SITLNET_DEFAULT_IMAGES_DIR;
  int code = kExitOk;
  const int status = ReportErrors("run", kExitUsage, [&] {
    code = runner::RunScenario(options).exit_code;
    return kExitOk;
  });
  return status != kExitOk ? status : code;
}

}  // namespace sitlnet::cli

// `sitlnet run SCENARIO ...`: the whole pipeline (runner/runner.h).
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/options.h"
#include "runner/runner.h"
#include "view/view.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kRunDescription =
    "Brings SCENARIO up, starts the simulated 802.11 medium, the MuJoCo physics,\n"
    "every robot's image and the coordinator, runs for the scenario's duration\n"
    "(or --duration seconds of simulated time), writes the run folder (default\n"
    "runs/<scenario>-<UTC time>: scenario, trajectories.csv, metrics.csv,\n"
    "medium.pcap, deliveries.csv, connectivity.csv, robots/<name>.log,\n"
    "summary.json, PNG plots; docs/run.md) and tears everything down. Ctrl-C\n"
    "stops in order.\n"
    "Images are looked up in $SITLNET_IMAGES, else the source tree's robot_images/.\n"
    "In realtime pacing sitlnet's own threads ask for SCHED_FIFO priority\n"
    "(--rt-priority); the images run at normal priority.\n"
    "Each image runs in a sandbox of its own (bubblewrap: own PID and mount\n"
    "namespaces, host files read-only, no capabilities; manifest `sandbox: NONE`\n"
    "to opt out) and, in realtime pacing at a realtime factor other than 1, in\n"
    "dilated time (libfaketime; manifest `time: WALL` to opt out); timing's\n"
    "ros2_clock_hz puts the simulation's time on ROS 2's /clock in every robot\n"
    "(docs/security.md, docs/time.md).\n";

constexpr const char* kRunExitCodes =
    "exit codes: 0 ok, 1 failure (a robot failed with on_robot_failure STOP, a\n"
    "component failed, the remote medium's connector did not come, was refused or\n"
    "vanished), 2 usage or bad scenario, 3 missing privileges, 130 interrupted\n"
    "(outputs written so far are complete).";

// `--view [ADDR:PORT]`: where the live view listens, and whether another address is allowed.
struct LiveViewArguments {
  CLI::Option* option = nullptr;
  std::string listen;
  bool allow_remote = false;
};

// The live view of the run `options` describes, bound and serving; its URL on stderr.
std::unique_ptr<view::LiveView> StartLiveView(const runner::RunOptions& options,
                                              const LiveViewArguments& arguments) {
  const view::ListenAddress listen = view::ParseListenAddress(
      arguments.listen.empty() ? view::kDefaultListen : arguments.listen, arguments.allow_remote);
  const Scenario scenario =
      runner::ApplyRunOverrides(LoadScenarioFile(options.scenario_path), options);
  auto live =
      std::make_unique<view::LiveView>(scenario, options.out_dir, listen, SITLNET_VIEW_WEB_DIR);
  std::fprintf(stderr, "sitlnet run: live view at %s\n", live->url().c_str());
  return live;
}

std::string SelfExe() {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return "sitlnet";
  path[n] = '\0';
  return path;
}

}  // namespace

void LocateImages(runner::RunOptions* options) {
  options->sitlnet_exe = SelfExe();
  const char* images = std::getenv("SITLNET_IMAGES");
  options->images_root = images ? images : SITLNET_DEFAULT_IMAGES_DIR;
}

Command AddRunCommand(CLI::App& sitlnet) {
  CLI::App* run =
      sitlnet.add_subcommand("run", "fly a scenario: robots, medium, physics, images, outputs");
  run->footer(std::string(kRunDescription) + "\n" + kRunExitCodes);
  auto options = std::make_shared<runner::RunOptions>();
  run->add_option("SCENARIO", options->scenario_path, "the scenario file")->required();
  run->add_option("--out", options->out_dir, "the run folder (default runs/<scenario>-<UTC time>)")
      ->type_name("DIR");
  // A number here; its bounds (0, a year] are RunScenario's, checked once there.
  run->add_option("--duration", options->duration_s,
                  "seconds of simulated time, at most a year (overrides timing.duration_ms)")
      ->type_name("S");
  run->add_option_function<std::string>(
         "--pacing",
         [options](const std::string& pacing) { options->pacing = clock::ParsePacing(pacing); },
         "realtime (against the wall clock) or lockstep (as fast as the host allows, "
         "reproducible); overrides timing.pacing")
      ->type_name("realtime|lockstep")
      ->check(CLI::IsMember({"realtime", "lockstep"}).description(""));
  AddSeedOption(*run, &options->seed);
  AddNoShadowingOption(*run, &options->no_shadowing);
  run->add_flag_function(
      "--no-progress", [options](int64_t) { options->progress = false; },
      "no live progress line on stderr");
  run->add_flag_function(
      "--no-losses", [options](int64_t) { options->record_losses = false; },
      "no losses.csv.gz and links.csv (the cause of every lost frame; docs/run.md)");
  AddRtPriorityOption(*run, &options->realtime_priority);
  AddGcsOption(*run, &options->gcs);
  CLI::Option* listen =
      run->add_option("--listen", options->listen,
                      "listen on HOST:PORT (0.0.0.0:7100; port 0 picks one, printed; or "
                      "unix:/path) for peers on other hosts, then run. With --remote network: "
                      "the 802.11 medium model runs on another host; wait for `sitlnet medium "
                      "SCENARIO --connect THIS_HOST:PORT` there (same scenario file, same --seed "
                      "and --no-shadowing); the robots' TAPs and physics stay here. For a "
                      "scenario with nodes: wait for every node's `sitlnet node SCENARIO --node "
                      "NAME --connect THIS_HOST:PORT` (same --seed and --pacing); the robots run "
                      "there, the medium and every output here (docs/scale-out.md). Lockstep "
                      "pacing only")
          ->type_name("HOST:PORT");
  auto remote = std::make_shared<std::string>();
  CLI::Option* remote_option =
      run->add_option("--remote", *remote,
                      "the side that runs on another host: network (physics serves the robots' "
                      "ctl0 here; docs/coordinator.md)")
          ->type_name("network")
          ->check(CLI::IsMember({"network"}).description(""));
  remote_option->needs(listen);
  AddPeerTimeoutOption(*run, "--remote-timeout", "longest wait for the medium to connect",
                       &options->remote_wait_ns);
  AddPeerTimeoutOption(*run, "--node-timeout",
                       "a scenario with nodes: longest wait for every node to connect",
                       &options->node_wait_ns, 120)
      ->needs(listen);
  run->add_flag("--one-host", options->one_host,
                "a scenario with nodes: run every robot here, ignoring `nodes` (the reference "
                "of a run over node hosts: the same outputs, byte for byte)")
      ->excludes(listen);
  AddSecretFileOption(*run, &options->secret_file)->needs(listen);
  auto view_arguments = std::make_shared<LiveViewArguments>();
  view_arguments->option =
      run->add_option("--view", view_arguments->listen,
                      std::string("serve a live view of the run on ADDR:PORT (default ") +
                          view::kDefaultListen +
                          "; port 0 picks one), printed on stderr; it never slows the run "
                          "(docs/view.md)")
          ->type_name("[ADDR:PORT]")
          ->expected(0, 1);
  run->add_flag("--view-allow-remote", view_arguments->allow_remote,
                "let --view listen on an address other than loopback")
      ->needs(view_arguments->option);
  return {run, [options, remote, view_arguments] {
            options->remote_network = !remote->empty();
            LocateImages(options.get());
            int code = kExitOk;
            const int status = ReportErrors("run", kExitUsage, [&] {
              std::unique_ptr<view::LiveView> live;
              if (view_arguments->option->count() > 0) {
                try {
                  live = StartLiveView(*options, *view_arguments);
                } catch (const view::ListenError& error) {
                  std::fprintf(stderr, "sitlnet run: %s\n", error.what());
                  return static_cast<int>(kExitFailure);
                }
                options->live = live->sink();
              }
              code = runner::RunScenario(*options).exit_code;
              if (live) std::fprintf(stderr, "sitlnet run: %s\n", live->CostLine().c_str());
              return static_cast<int>(kExitOk);
            });
            return status != kExitOk ? status : code;
          }};
}

}  // namespace sitlnet::cli

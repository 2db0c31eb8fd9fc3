// `sitlnet node SCENARIO --node NAME --connect HOST:PORT`: a node host of a fleet
// (runner/node_run.h).
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/options.h"
#include "runner/node_run.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kNodeFooter =
    "Runs the robots of node NAME of SCENARIO (a scenario with nodes) for the\n"
    "central host's `sitlnet run SCENARIO --listen HOST:PORT`: brings up their\n"
    "namespaces, the physics of these robots only and their images, connects to\n"
    "HOST:PORT (retrying while nothing listens, up to --connect-timeout S), and\n"
    "serves every iteration until the run ends. Frames of its robots go up to\n"
    "the one medium on the central host; deliveries and poses cross the same\n"
    "link. The run's outputs are written on the central host; the robots' logs\n"
    "are in --out DIR/robots (default runs/<scenario>-<node>). Then it stops the\n"
    "robots and takes its namespaces down. The node that runs the scenario's\n"
    "ground station relays its MAVLink to a GCS (--gcs; gcs.tlog in --out).\n"
    "Give the central's --seed and --pacing: both ends must load the same\n"
    "scenario. Two nodes on one host need\n"
    "a network and mount namespace each, as pods have (docs/scale-out.md).\n"
    "\n"
    "exit codes: 0 the run ended (the central sent Stop), 1 failed (the central\n"
    "unreachable, the handshake refused, a robot failed, the link lost), 2 usage\n"
    "or bad scenario file, 3 missing privileges, 130 interrupted.";

struct NodeArguments {
  runner::NodeOptions options;
  bool linger = false;
};

// After the run: idle until SIGINT or SIGTERM, so that a pod's restart policy does not start
// the node again.
void Linger() {
  const StopSignal stop;
  std::fprintf(stderr, "sitlnet node: lingering until SIGTERM (--linger)\n");
  stop.Wait();
}

int Node(NodeArguments& arguments) {
  LocateImages(&arguments.options.run);
  const int loaded = ReportErrors("node", kExitUsage, [&] {
    LoadScenarioFile(arguments.options.run.scenario_path);  // A bad file is a usage error.
    return kExitOk;
  });
  if (loaded != kExitOk) return loaded;
  std::string reason;
  const int status = ReportErrors("node", kExitFailure, [&] {
    reason = runner::ServeNodeHost(arguments.options);
    return kExitOk;
  });
  if (status == kExitOk) {
    std::fprintf(stderr, "sitlnet node: %s: stopped: %s\n", arguments.options.node.c_str(),
                 reason.c_str());
  }
  const int code = status != kExitOk ? status : reason == "interrupted" ? 130 : kExitOk;
  if (arguments.linger && reason != "interrupted") Linger();
  return code;
}

}  // namespace

Command AddNodeCommand(CLI::App& sitlnet) {
  CLI::App* node = sitlnet.add_subcommand(
      "node", "run a node host's robots for a fleet's central `sitlnet run` (issue 35)");
  node->footer(kNodeFooter);
  auto arguments = std::make_shared<NodeArguments>();
  runner::NodeOptions& options = arguments->options;
  node->add_option("SCENARIO", options.run.scenario_path, "the scenario file (with nodes)")
      ->required();
  node->add_option("--node", options.node, "this host's node: one of the scenario's nodes")
      ->type_name("NAME")
      ->required();
  node->add_option("--connect", options.connect,
                   "the central host's --listen address (HOST:PORT or unix:/path)")
      ->type_name("HOST:PORT")
      ->required();
  AddSecretFileOption(*node, &options.run.secret_file);
  node->add_option_function<std::string>(
          "--pacing",
          [&options](const std::string& pacing) {
            options.run.pacing = clock::ParsePacing(pacing);
          },
          "as the central's --pacing (overrides timing.pacing)")
      ->type_name("realtime|lockstep")
      ->check(CLI::IsMember({"realtime", "lockstep"}).description(""));
  AddSeedOption(*node, &options.run.seed);
  node->add_option("--out", options.run.out_dir,
                   "folder of the robots' logs (default runs/<scenario>-<node>)")
      ->type_name("DIR");
  AddGcsOption(*node, &options.run.gcs);
  AddPeerTimeoutOption(*node, "--connect-timeout",
                       "longest wait for the central to listen and answer, retrying meanwhile",
                       &options.connect_timeout_ns, 120);
  node->add_flag("--linger", arguments->linger,
                 "after the run, idle until SIGTERM (a pod's container then is not restarted)");
  return {node, [arguments] { return Node(*arguments); }};
}

}  // namespace sitlnet::cli

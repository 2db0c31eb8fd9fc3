// `sitlnet node`: a node host of a fleet (issue 35). It brings up its robots' namespaces, the
// physics of its robots only and their images, connects to the central host's `sitlnet run`,
// and serves every iteration: deliveries written to its robots' TAPs, their frames drained up
// after their commands, their poses up at the end. The run's outputs are the central's; a node
// writes its robots' logs (<out>/robots/<robot>.log).
#ifndef SITLNET_RUNNER_NODE_RUN_H_
#define SITLNET_RUNNER_NODE_RUN_H_

#include <string>

#include "common/common.h"
#include "runner/runner.h"

namespace sitlnet::runner {

struct NodeOptions {
  // scenario_path, seed and pacing (as the central's, so both hash the same scenario),
  // secret_file, out_dir (empty: runs/<scenario>-<node>), sitlnet_exe and images_root. The
  // robots' shared setup and supervision begin their lines with "sitlnet node".
  RunOptions run = [] {
    RunOptions node;
    node.program = "sitlnet node";
    return node;
  }();
  std::string node;                           // Its name in the scenario's nodes.
  std::string connect;                        // The central's --listen: HOST:PORT or unix:/path.
  TimeNs connect_timeout_ns = 120 * kNsPerS;  // Retrying while nothing listens.
};

// Serves the run as node options.node and tears everything down. Returns the reason of the
// central's Stop; throws Error for bad input (before anything is created) and for a failure
// (after tearing down), PrivilegeError without privileges.
std::string ServeNodeHost(const NodeOptions& options);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_NODE_RUN_H_

// `sitlnet run` of a scenario with `nodes` (issue 35): this host is the fleet's central host. It
// runs the coordinator, the one 802.11 medium and its bridge, and writes every output of the run;
// the robots, their namespaces and their physics run on the node hosts (`sitlnet node`), linked
// here over --listen. Nothing namespaced is created here, and no privilege is needed.
#ifndef SITLNET_RUNNER_FLEET_RUN_H_
#define SITLNET_RUNNER_FLEET_RUN_H_

#include "common/common.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// Accepts every node of `scenario` on options.listen (within options.node_wait_ns), before
// anything exists, then runs as RunScenario does. `report` holds the run folder.
RunReport RunOnNodeHosts(const Scenario& scenario, const RunOptions& options, RunReport report,
                         TimeNs begin_ns);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_FLEET_RUN_H_

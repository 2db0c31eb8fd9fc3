// End of a run: connectivity.csv, summary.json and the plots.
#ifndef SITLNET_RUNNER_SUMMARY_H_
#define SITLNET_RUNNER_SUMMARY_H_

#include <optional>
#include <string>
#include <vector>

#include "coordinator/metrics.h"
#include "physics_mujoco/physics_mujoco.h"
#include "run_formats/run_formats.h"
#include "runner/medium_records.h"
#include "runner/robot_slot.h"
#include "runner/runner.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

// Window of the communication graph: a link counts while a frame crossed it
// within the last 2 s (the flocker's neighbour timeout tau of the case study).
inline constexpr TimeNs kConnectivityWindowNs = 2 * kNsPerS;
inline constexpr TimeNs kConnectivitySampleNs = 100 * kNsPerMs;

// `physics`: null when the robots' physics ran on node hosts (each robot's "physics": null).
// `records`: the medium's (connectivity, and the loss log's delivery by link class).
// `closest`: the closest approach over trajectories.csv's samples (null: "separation" null).
void WriteSummaryAndPlots(const Scenario& scenario, const RunReport& report,
                          const coordinator::MetricsSummary& metrics, int64_t iterations_done,
                          const std::vector<RobotSlot>& robots, tapbridge::BridgeCore& bridge,
                          const physics::PhysicsServer* physics, MediumRecords& records,
                          const std::optional<run_formats::ClosestApproach>& closest,
                          const std::string& failure);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_SUMMARY_H_

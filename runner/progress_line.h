// The live progress line of `sitlnet run` on stderr: virtual time, speed, robots alive, frames,
// in realtime pacing the iteration lag, the autopilots' rates (docs/run.md, "The progress
// line"), and with a GCS relay the vehicles its GCS hears.
#ifndef SITLNET_RUNNER_PROGRESS_LINE_H_
#define SITLNET_RUNNER_PROGRESS_LINE_H_

#include <algorithm>
#include <string>
#include <vector>

#include "common/common.h"
#include "gcs_link/gcs_link.h"
#include "physics_mujoco/physics_mujoco.h"
#include "runner/iteration_observer.h"
#include "runner/robot_slot.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

// Observes the network side's iterations (it reads the bridge's counters). A terminal gets one
// line redrawn twice a second; a log file a line every 5 s.
class ProgressLine final : public IterationObserver {
 public:
  // `enabled` false: prints nothing. `bridge`, `robots`, `physics` (null: the physics runs on
  // node hosts; no autopilot rates) and `gcs_relay` (null: none) must outlive this. `realtime`:
  // the line shows the iteration lag.
  ProgressLine(bool enabled, tapbridge::BridgeCore* bridge, const std::vector<RobotSlot>* robots,
               TimeNs duration_ns, const gcs::GcsRelay* gcs_relay = nullptr,
               const physics::PhysicsServer* physics = nullptr, bool realtime = false);
  void IterationBegins(const proto::coord::Start& start) override;
  void IterationEnded(const proto::coord::Start& start) override;
  // An iteration's lag (the coordinator's IterationMetrics): the line shows the largest since
  // the last line.
  void IterationLag(TimeNs lag_ns) { lag_max_ns_ = std::max(lag_max_ns_, lag_ns); }
  // Ends the progress line (a newline if one was printed): call before any other stderr line.
  void Finish();

 private:
  void Print(TimeNs now_ns);
  // " autopilots N at A-B % of their rate" over the wall time since the last line, "" without
  // autopilots.
  std::string AutopilotRates(TimeNs wall_now_ns);

  bool enabled_;
  tapbridge::BridgeCore& bridge_;
  const std::vector<RobotSlot>& robots_;
  TimeNs duration_ns_;
  const gcs::GcsRelay* gcs_relay_;
  const physics::PhysicsServer* physics_;
  bool realtime_;
  TimeNs lag_max_ns_ = 0;
  std::vector<uint64_t> answers_before_;  // Per robot, at the last line.
  TimeNs last_print_wall_ns_ = 0;
  std::string rates_text_;  // The last autopilot rates shown, until new ones are due.
  TimeNs wall_start_ns_ = 0;
  TimeNs next_print_wall_ns_ = 0;
  bool printed_ = false;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_PROGRESS_LINE_H_

// The live progress line of `sitlnet run` on stderr: virtual time, speed, robots alive, frames,
// and with a GCS relay the vehicles its GCS hears.
#ifndef SITLNET_RUNNER_PROGRESS_LINE_H_
#define SITLNET_RUNNER_PROGRESS_LINE_H_

#include <vector>

#include "common/common.h"
#include "gcs_link/gcs_link.h"
#include "runner/iteration_observer.h"
#include "runner/robot_slot.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

// Observes the network side's iterations (it reads the bridge's counters). A terminal gets one
// line redrawn twice a second; a log file a line every 5 s.
class ProgressLine final : public IterationObserver {
 public:
  // `enabled` false: prints nothing. `bridge`, `robots` and `gcs_relay` (null: none) must
  // outlive this.
  ProgressLine(bool enabled, tapbridge::BridgeCore* bridge, const std::vector<RobotSlot>* robots,
               TimeNs duration_ns, const gcs::GcsRelay* gcs_relay = nullptr);
  void IterationBegins(const proto::coord::Start& start) override;
  void IterationEnded(const proto::coord::Start& start) override;
  // Ends the progress line (a newline if one was printed): call before any other stderr line.
  void Finish();

 private:
  void Print(TimeNs now_ns);

  bool enabled_;
  tapbridge::BridgeCore& bridge_;
  const std::vector<RobotSlot>& robots_;
  TimeNs duration_ns_;
  const gcs::GcsRelay* gcs_relay_;
  TimeNs wall_start_ns_ = 0;
  TimeNs next_print_wall_ns_ = 0;
  bool printed_ = false;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_PROGRESS_LINE_H_

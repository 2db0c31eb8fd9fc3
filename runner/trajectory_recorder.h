// trajectories.csv from the robots' poses as the coordinator carries them (proto Poses), the
// live view's samples of them, and the closest approach over them (summary.json "separation").
// One formatter for a run on one host (RecordingPhysics) and for a central host that receives
// the poses of its node hosts (issue 35): the same doubles, the same bytes.
#ifndef SITLNET_RUNNER_TRAJECTORY_RECORDER_H_
#define SITLNET_RUNNER_TRAJECTORY_RECORDER_H_

#include <optional>
#include <string>
#include <vector>

#include "common/common.h"
#include "physics_mujoco/physics_mujoco.h"
#include "run_formats/run_formats.h"
#include "sitlnet/coordinator.pb.h"

namespace sitlnet::runner {

class TrajectoryRecorder {
 public:
  // `frame`: the scenario's geodetic frame, for the rows' latitude, longitude and altitude.
  TrajectoryRecorder(const physics::GeodeticFrame& frame, const std::string& csv_path);

  // One row per robot at `time_ns`. `poses` holds every robot of the run in global index order,
  // with positions, orientations and velocities (physics_side::PosesFromWorld). Throws Error if
  // their counts disagree.
  void Record(TimeNs time_ns, const proto::coord::Poses& poses);
  void Flush() { csv_.Flush(); }
  // `sink` (may be null; outlives this) is told every sample too.
  void SetLiveSink(run_formats::LiveSink* sink) { live_ = sink; }
  // The closest two robots came at the samples recorded so far.
  const std::optional<run_formats::ClosestApproach>& closest_approach() const {
    return closest_approach_.closest();
  }

 private:
  physics::GeodeticFrame frame_;
  LineFile csv_;
  run_formats::LiveSink* live_ = nullptr;
  std::vector<run_formats::LivePose> live_poses_;  // Reused: no allocation per sample.
  run_formats::ClosestApproachTracker closest_approach_;
  std::vector<double> positions_m_;  // Reused: the sample's positions for the tracker.
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_TRAJECTORY_RECORDER_H_

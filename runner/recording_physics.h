// The run's physics simulator, recorded: trajectories.csv and the robots' shared /clock time.
#ifndef SITLNET_RUNNER_RECORDING_PHYSICS_H_
#define SITLNET_RUNNER_RECORDING_PHYSICS_H_

#include <optional>
#include <string>
#include <vector>

#include "common/common.h"
#include "coordinator/connector.h"
#include "physics_mujoco/physics_mujoco.h"
#include "ros2_clock/ros2_clock.h"
#include "run_formats/run_formats.h"
#include "runner/trajectory_recorder.h"

namespace sitlnet::runner {

// Physics simulator + trajectories.csv every `period_ns` of virtual time, from the poses the
// simulator reports (its initial poses, then each iteration's End): what a central host
// receives from its node hosts (issue 35). Runs on the physics connector's thread, so it
// touches only its own simulator.
class RecordingPhysics final : public coordinator::Simulator {
 public:
  // `frame`: the scenario's geodetic frame, for the rows' latitude, longitude and altitude.
  RecordingPhysics(coordinator::Simulator* inner, const physics::GeodeticFrame& frame,
                   const std::string& csv_path, TimeNs period_ns);
  proto::coord::Poses InitialPoses() override { return inner_.InitialPoses(); }
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;
  // Each iteration's end time, once the physics has reached it, goes there too (the robots'
  // /clock publishers read it).
  void ShareTimeWith(ros2_clock::SharedVirtualTime* shared) { shared_time_ = shared; }
  void Flush() { recorder_.Flush(); }
  const std::optional<run_formats::ClosestApproach>& closest_approach() const {
    return recorder_.closest_approach();
  }
  // `sink` (may be null; outlives this) is told every sample too.
  void SetLiveSink(run_formats::LiveSink* sink) { recorder_.SetLiveSink(sink); }

 private:
  coordinator::Simulator& inner_;
  TrajectoryRecorder recorder_;
  TimeNs period_ns_;
  TimeNs next_sample_ns_ = 0;
  ros2_clock::SharedVirtualTime* shared_time_ = nullptr;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RECORDING_PHYSICS_H_

// A physics connector, recorded: trajectories.csv from the poses its End carries. On a fleet's
// central host (issue 35) the physics runs on node hosts, so the rows are written from the merged
// poses, with the formatter a run on one host uses (TrajectoryRecorder): the same bytes.
#ifndef SITLNET_RUNNER_RECORDING_CONNECTOR_H_
#define SITLNET_RUNNER_RECORDING_CONNECTOR_H_

#include <optional>
#include <string>

#include "common/common.h"
#include "coordinator/coordinator.h"
#include "physics_mujoco/physics_mujoco.h"
#include "runner/trajectory_recorder.h"

namespace sitlnet::runner {

// Records `inner`'s initial poses at time 0 and its End's poses every `period_ns` of virtual
// time, at the same instants as RecordingPhysics. `inner` must outlive this.
class RecordingConnector final : public coordinator::Connector {
 public:
  RecordingConnector(coordinator::Connector* inner, const physics::GeodeticFrame& frame,
                     const std::string& csv_path, TimeNs period_ns);

  const proto::coord::Poses& initial_poses() const override { return inner_.initial_poses(); }
  void Begin(const proto::coord::Start& start, const coordinator::WaitLimits& limits) override;
  bool AwaitCommandsCollected(uint64_t iteration, const coordinator::WaitLimits& limits) override {
    return inner_.AwaitCommandsCollected(iteration, limits);
  }
  bool Finish(uint64_t iteration, proto::coord::End* end,
              const coordinator::WaitLimits& limits) override;
  bool runs_on_caller_thread() const override { return inner_.runs_on_caller_thread(); }
  void Stop(const std::string& reason) override { inner_.Stop(reason); }
  void Flush() { recorder_.Flush(); }
  const std::optional<run_formats::ClosestApproach>& closest_approach() const {
    return recorder_.closest_approach();
  }

 private:
  coordinator::Connector& inner_;
  TrajectoryRecorder recorder_;
  TimeNs period_ns_;
  TimeNs next_sample_ns_ = 0;
  TimeNs end_ns_ = 0;  // Of the iteration begun.
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RECORDING_CONNECTOR_H_

#include "runner/recording_physics.h"

#include <cmath>

#include "runner/outputs.h"

namespace sitlnet::runner {

RecordingPhysics::RecordingPhysics(coordinator::Simulator* inner, const physics::World* world,
                                   const physics::GeodeticFrame& frame, const std::string& csv_path,
                                   TimeNs period_ns)
    : inner_(*inner),
      world_(*world),
      frame_(frame),
      csv_(csv_path, kTrajectoryHeader),
      period_ns_(period_ns) {}

void RecordingPhysics::Record(TimeNs time_ns) {
  live_poses_.resize(live_ != nullptr ? world_.robot_count() : 0);
  for (int i = 0; i < world_.robot_count(); ++i) {
    const physics::RobotPose pose = world_.Pose(i);
    PoseRow row;
    row.time_ns = time_ns;
    row.robot = i;
    row.x_m = pose.position_m.x;
    row.y_m = pose.position_m.y;
    row.z_m = pose.position_m.z;
    row.qw = pose.orientation.w;
    row.qx = pose.orientation.x;
    row.qy = pose.orientation.y;
    row.qz = pose.orientation.z;
    row.vx_m_s = pose.velocity_m_s.x;
    row.vy_m_s = pose.velocity_m_s.y;
    row.vz_m_s = pose.velocity_m_s.z;
    const physics::GeodeticPoint where = frame_.ToGeodetic(pose.position_m);
    row.latitude_deg = where.latitude_deg;
    row.longitude_deg = where.longitude_deg;
    row.altitude_m = where.altitude_m;
    csv_.Append(FormatPoseRow(row));
    if (live_ != nullptr) {
      live_poses_[i] = {row.x_m, row.y_m, row.z_m, std::hypot(row.vx_m_s, row.vy_m_s, row.vz_m_s)};
    }
  }
  if (live_ != nullptr) live_->Poses(time_ns, live_poses_);
}

void RecordingPhysics::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                    coordinator::IterationContext& context) {
  if (start.start_ns() == 0) Record(0);
  inner_.RunIteration(start, end, context);
  if (shared_time_ != nullptr) shared_time_->Store(start.end_ns());
  if (start.end_ns() >= next_sample_ns_ + period_ns_) {
    Record(start.end_ns());
    next_sample_ns_ = start.end_ns();
  }
}

}  // namespace sitlnet::runner

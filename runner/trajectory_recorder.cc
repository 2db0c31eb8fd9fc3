#include "runner/trajectory_recorder.h"

#include <cmath>

#include "run_formats/run_formats.h"

namespace sitlnet::runner {

TrajectoryRecorder::TrajectoryRecorder(const physics::GeodeticFrame& frame,
                                       const std::string& csv_path)
    : frame_(frame), csv_(csv_path, run_formats::kTrajectoryHeader) {}

void TrajectoryRecorder::Record(TimeNs time_ns, const proto::coord::Poses& poses) {
  const int robots = poses.position_m_size() / 3;
  if (poses.position_m_size() != 3 * robots || poses.orientation_wxyz_size() != 4 * robots ||
      poses.velocity_m_s_size() != 3 * robots) {
    throw Error("trajectories.csv at " + std::to_string(time_ns) + " ns: poses hold " +
                std::to_string(poses.position_m_size()) + " position, " +
                std::to_string(poses.orientation_wxyz_size()) + " orientation and " +
                std::to_string(poses.velocity_m_s_size()) +
                " velocity values, not 3, 4 and 3 per robot");
  }
  live_poses_.resize(live_ != nullptr ? robots : 0);
  for (int i = 0; i < robots; ++i) {
    run_formats::PoseRow row;
    row.time_ns = time_ns;
    row.robot = i;
    row.x_m = poses.position_m(3 * i);
    row.y_m = poses.position_m(3 * i + 1);
    row.z_m = poses.position_m(3 * i + 2);
    row.qw = poses.orientation_wxyz(4 * i);
    row.qx = poses.orientation_wxyz(4 * i + 1);
    row.qy = poses.orientation_wxyz(4 * i + 2);
    row.qz = poses.orientation_wxyz(4 * i + 3);
    row.vx_m_s = poses.velocity_m_s(3 * i);
    row.vy_m_s = poses.velocity_m_s(3 * i + 1);
    row.vz_m_s = poses.velocity_m_s(3 * i + 2);
    const physics::GeodeticPoint where = frame_.ToGeodetic({row.x_m, row.y_m, row.z_m});
    row.latitude_deg = where.latitude_deg;
    row.longitude_deg = where.longitude_deg;
    row.altitude_m = where.altitude_m;
    csv_.Append(run_formats::FormatPoseRow(row));
    if (live_ != nullptr) {
      live_poses_[i] = {row.x_m, row.y_m, row.z_m, std::hypot(row.vx_m_s, row.vy_m_s, row.vz_m_s)};
    }
  }
  if (live_ != nullptr) live_->Poses(time_ns, live_poses_);
  positions_m_.assign(poses.position_m().begin(), poses.position_m().end());
  closest_approach_.Sample(time_ns, positions_m_);
}

}  // namespace sitlnet::runner

#include "fleet/node_poses.h"

#include <cmath>

namespace sitlnet::fleet {

std::optional<std::string> FindBrokenPoses(const proto::coord::Poses& poses, size_t robots) {
  const size_t positions = static_cast<size_t>(poses.position_m_size());
  const size_t orientations = static_cast<size_t>(poses.orientation_wxyz_size());
  const size_t velocities = static_cast<size_t>(poses.velocity_m_s_size());
  // Velocities are optional as a whole (a physics without them sends none), never in part.
  if (positions != 3 * robots || orientations != 4 * robots ||
      (velocities != 0 && velocities != 3 * robots)) {
    return "sent " + std::to_string(positions) + " position, " + std::to_string(orientations) +
           " orientation and " + std::to_string(velocities) +
           " velocity numbers, not 3, 4 and 3 (or 0) for each of its " + std::to_string(robots) +
           " robots";
  }
  // A NaN or an infinity is no place a robot can be: the medium's distances and the run's
  // trajectories.csv would carry it on. Only a broken or hostile peer sends one.
  const auto first_not_finite = [](const google::protobuf::RepeatedField<double>& numbers) {
    for (int i = 0; i < numbers.size(); ++i) {
      if (!std::isfinite(numbers.Get(i))) return i;
    }
    return -1;
  };
  const struct {
    const char* what;
    int per_robot;
    const google::protobuf::RepeatedField<double>& numbers;
  } fields[] = {{"position", 3, poses.position_m()},
                {"orientation", 4, poses.orientation_wxyz()},
                {"velocity", 3, poses.velocity_m_s()}};
  for (const auto& field : fields) {
    if (const int at = first_not_finite(field.numbers); at >= 0) {
      return "sent its robot " + std::to_string(at / field.per_robot + 1) + "'s " + field.what +
             " (of " + std::to_string(robots) + " robots) with a number that is not finite";
    }
  }
  return std::nullopt;
}

void PlacePoses(const proto::coord::Poses& node, const std::vector<int>& robots,
                proto::coord::Poses* all) {
  const bool velocities = node.velocity_m_s_size() > 0;
  if (velocities && all->velocity_m_s_size() == 0) {
    all->mutable_velocity_m_s()->Resize(all->position_m_size(), 0.0);
  }
  for (size_t i = 0; i < robots.size(); ++i) {
    const int robot = robots[i];
    for (int c = 0; c < 3; ++c) all->set_position_m(3 * robot + c, node.position_m(3 * i + c));
    for (int c = 0; c < 4; ++c) {
      all->set_orientation_wxyz(4 * robot + c, node.orientation_wxyz(4 * i + c));
    }
    if (!velocities) continue;
    for (int c = 0; c < 3; ++c) {
      all->set_velocity_m_s(3 * robot + c, node.velocity_m_s(3 * i + c));
    }
  }
}

}  // namespace sitlnet::fleet

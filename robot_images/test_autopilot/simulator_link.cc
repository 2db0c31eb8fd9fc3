#include "robot_images/test_autopilot/simulator_link.h"

#include <cmath>

namespace sitlnet::test_autopilot {

Eigen::Vector3d NedToEnu(const Eigen::Vector3d& ned) { return {ned.y(), ned.x(), -ned.z()}; }

Eigen::Vector3d FrdToFlu(const Eigen::Vector3d& frd) { return {frd.x(), -frd.y(), -frd.z()}; }

Eigen::Quaterniond FrdInNedToFluInEnu(const Eigen::Quaterniond& q) {
  // body FLU -> world ENU = (NED -> ENU) * (FRD -> NED) * (FLU -> FRD).
  static const Eigen::Quaterniond ned_to_enu(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d(1, 1, 0).normalized()));
  static const Eigen::Quaterniond flu_to_frd(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  Eigen::Quaterniond result = ned_to_enu * q * flu_to_frd;
  result.normalize();
  return result;
}

}  // namespace sitlnet::test_autopilot

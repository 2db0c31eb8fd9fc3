#include "robot_images/test_autopilot/local_frame.h"

namespace sitlnet::test_autopilot {

LocalFrame::LocalFrame(const GeodeticPosition& origin)
    : origin_(origin), plane_(origin.latitude_deg, origin.longitude_deg, origin.altitude_m) {}

Eigen::Vector3d LocalFrame::ToEnu(const GeodeticPosition& position) const {
  Eigen::Vector3d enu;
  plane_.Forward(position.latitude_deg, position.longitude_deg, position.altitude_m, enu.x(),
                 enu.y(), enu.z());
  return enu;
}

GeodeticPosition LocalFrame::ToGeodetic(const Eigen::Vector3d& enu_m) const {
  GeodeticPosition position;
  plane_.Reverse(enu_m.x(), enu_m.y(), enu_m.z(), position.latitude_deg, position.longitude_deg,
                 position.altitude_m);
  return position;
}

}  // namespace sitlnet::test_autopilot

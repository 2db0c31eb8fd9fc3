// The test autopilot's map: metres east, north and up of a geodetic origin (its --origin, by
// default sitlnet's default origin), on the plane tangent to the WGS-84 ellipsoid there
// (GeographicLib's LocalCartesian), as a small autopilot's local frame is. Within a few hundred
// metres this is sitlnet's world frame to the millimetre (docs/autopilots.md).
#ifndef SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_LOCAL_FRAME_H_
#define SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_LOCAL_FRAME_H_

#include <Eigen/Core>
#include <GeographicLib/LocalCartesian.hpp>

namespace sitlnet::test_autopilot {

struct GeodeticPosition {
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;  // altitude above mean sea level
};

class LocalFrame {
 public:
  explicit LocalFrame(const GeodeticPosition& origin);
  Eigen::Vector3d ToEnu(const GeodeticPosition& position) const;
  GeodeticPosition ToGeodetic(const Eigen::Vector3d& enu_m) const;
  const GeodeticPosition& origin() const { return origin_; }

 private:
  GeodeticPosition origin_;
  GeographicLib::LocalCartesian plane_;
};

}  // namespace sitlnet::test_autopilot

#endif  // SITLNET_ROBOT_IMAGES_TEST_AUTOPILOT_LOCAL_FRAME_H_

#include "physics_mujoco/physics_mujoco.h"

#include <GeographicLib/AzimuthalEquidistant.hpp>

namespace sitlnet::physics {
namespace {

const GeographicLib::AzimuthalEquidistant& Projection() {
  static const GeographicLib::AzimuthalEquidistant projection(GeographicLib::Geodesic::WGS84());
  return projection;
}

}  // namespace

GeodeticFrame::GeodeticFrame(const proto::GeodeticOrigin& origin)
    : origin_{origin.latitude_deg(), origin.longitude_deg(), origin.altitude_m()} {}

GeodeticPoint GeodeticFrame::ToGeodetic(const Vec3d& enu_m) const {
  GeodeticPoint point;
  Projection().Reverse(origin_.latitude_deg, origin_.longitude_deg, enu_m.x, enu_m.y,
                       point.latitude_deg, point.longitude_deg);
  point.altitude_m = origin_.altitude_m + enu_m.z;
  return point;
}

Vec3d GeodeticFrame::ToEnu(const GeodeticPoint& point) const {
  Vec3d enu_m;
  Projection().Forward(origin_.latitude_deg, origin_.longitude_deg, point.latitude_deg,
                       point.longitude_deg, enu_m.x, enu_m.y);
  enu_m.z = point.altitude_m - origin_.altitude_m;
  return enu_m;
}

}  // namespace sitlnet::physics

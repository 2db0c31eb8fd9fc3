// The scenario's local ENU frame on the WGS-84 ellipsoid (docs/autopilots.md, "Geodetic origin").
#ifndef SITLNET_PHYSICS_MUJOCO_GEODETIC_H_
#define SITLNET_PHYSICS_MUJOCO_GEODETIC_H_

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

// A place on Earth: WGS-84 latitude and longitude, altitude above mean sea level.
struct GeodeticPoint {
  double latitude_deg = 0;   // North positive.
  double longitude_deg = 0;  // East positive, in [-180, 180].
  double altitude_m = 0;
};

// Maps world ENU positions (metres from the scenario's origin) to geodetic coordinates and back.
// Horizontally by the azimuthal equidistant projection on the WGS-84 ellipsoid centred at the
// origin (GeographicLib, C. F. F. Karney, "Algorithms for geodesics", J. Geodesy 87, 2013): the
// point (x, y) lies at geodesic distance hypot(x, y) from the origin, at azimuth atan2(x, y)
// from north, exact to the nanometre. Vertically, altitude = origin altitude + z: the flat
// simulated ground follows the ellipsoid (geoid height ignored). Cheap to copy.
class GeodeticFrame {
 public:
  explicit GeodeticFrame(const proto::GeodeticOrigin& origin);

  GeodeticPoint ToGeodetic(const Vec3d& enu_m) const;
  // Inverse of ToGeodetic (to the nanometre within 1000 km of the origin).
  Vec3d ToEnu(const GeodeticPoint& point) const;
  const GeodeticPoint& origin() const { return origin_; }

 private:
  GeodeticPoint origin_;
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_GEODETIC_H_

// GeodeticFrame against published WGS-84 figures and hand-computed radii of curvature.
#include "physics_mujoco/physics_mujoco.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sitlnet::physics {
namespace {

proto::GeodeticOrigin Origin(double latitude_deg, double longitude_deg, double altitude_m) {
  proto::GeodeticOrigin origin;
  origin.set_latitude_deg(latitude_deg);
  origin.set_longitude_deg(longitude_deg);
  origin.set_altitude_m(altitude_m);
  return origin;
}

TEST(GeodeticTest, OriginAndAltitude) {
  const GeodeticFrame frame(proto::GeodeticOrigin{});  // PX4 SITL's default home
  const GeodeticPoint point = frame.ToGeodetic({0, 0, 12.5});
  EXPECT_DOUBLE_EQ(point.latitude_deg, 47.397742);
  EXPECT_DOUBLE_EQ(point.longitude_deg, 8.545594);
  EXPECT_DOUBLE_EQ(point.altitude_m, 488 + 12.5);
}

TEST(GeodeticTest, QuarterMeridianReachesThePole) {
  // WGS-84 quarter meridian, equator to pole: 10 001 965.729 m (e.g. Karney 2013, and the
  // meridian arc series for a = 6378137 m, f = 1/298.257223563).
  const GeodeticFrame frame(Origin(0, 0, 0));
  EXPECT_NEAR(frame.ToGeodetic({0, 10001965.729, 0}).latitude_deg, 90, 1e-8);
}

TEST(GeodeticTest, OneDegreeAlongTheEquator) {
  // The equator is a geodesic: 1 degree of it is 2 pi a / 360 = 111 319.490793 m.
  const GeodeticFrame frame(Origin(0, 10, 0));
  const GeodeticPoint point = frame.ToGeodetic({111319.490793, 0, 0});
  EXPECT_NEAR(point.longitude_deg, 11, 1e-9);
  EXPECT_NEAR(point.latitude_deg, 0, 1e-12);
}

TEST(GeodeticTest, SmallOffsetsFollowTheRadiiOfCurvature) {
  // At 47.397742 N: meridian radius M = a (1 - e^2) / (1 - e^2 sin^2 phi)^1.5 = 6 370 064.34 m,
  // prime vertical N = a / sqrt(1 - e^2 sin^2 phi) = 6 389 735.35 m (WGS-84 a, f). 100 m north
  // is 100 / M rad = 0.000899454 deg; 100 m east is 100 / (N cos phi) rad = 0.001324683 deg.
  // Second-order terms at 100 m are below 1e-3 m (1e-8 deg).
  const GeodeticFrame frame(proto::GeodeticOrigin{});
  const GeodeticPoint north = frame.ToGeodetic({0, 100, 0});
  EXPECT_NEAR(north.latitude_deg - 47.397742, 0.000899454, 1e-8);
  EXPECT_NEAR(north.longitude_deg, 8.545594, 1e-12);
  const GeodeticPoint east = frame.ToGeodetic({100, 0, 0});
  EXPECT_NEAR(east.longitude_deg - 8.545594, 0.001324683, 1e-8);
  EXPECT_NEAR(east.latitude_deg, 47.397742, 1e-8);
}

TEST(GeodeticTest, RoundTripIsExact) {
  const GeodeticFrame frame(Origin(-33.9, 151.2, 20));
  for (const Vec3d enu : {Vec3d{1, 2, 3}, Vec3d{-2500, 800, -5}, Vec3d{40000, -35000, 120}}) {
    const Vec3d back = frame.ToEnu(frame.ToGeodetic(enu));
    EXPECT_NEAR(back.x, enu.x, 1e-6);
    EXPECT_NEAR(back.y, enu.y, 1e-6);
    EXPECT_NEAR(back.z, enu.z, 1e-9);
  }
}

}  // namespace
}  // namespace sitlnet::physics

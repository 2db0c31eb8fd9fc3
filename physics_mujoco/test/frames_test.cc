#include "physics_mujoco/frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sitlnet::physics {
namespace {

constexpr double kPi = std::numbers::pi;

Quat YawQuat(double yaw_rad) { return {std::cos(yaw_rad / 2), 0, 0, std::sin(yaw_rad / 2)}; }

TEST(FramesTest, VectorsSwapAxesAndFlipUp) {
  const Vec3d ned = EnuToNed({1, 2, 3});
  EXPECT_EQ(ned.x, 2);
  EXPECT_EQ(ned.y, 1);
  EXPECT_EQ(ned.z, -3);
  const Vec3d frd = FluToFrd({1, 2, 3});
  EXPECT_EQ(frd.x, 1);
  EXPECT_EQ(frd.y, -2);
  EXPECT_EQ(frd.z, -3);
}

TEST(FramesTest, NoseEastIsHeadingNinetyDegreesInNed) {
  // ENU yaw 0: nose east. NED heading is measured from north towards east: +90 deg.
  const Quat q = EnuFluToNedFrd(YawQuat(0));
  EXPECT_NEAR(YawRad(q), kPi / 2, 1e-12);
  // ENU yaw +90 deg (nose north): NED heading 0.
  EXPECT_NEAR(YawRad(EnuFluToNedFrd(YawQuat(kPi / 2))), 0, 1e-12);
}

TEST(FramesTest, NedAttitudeRotatesFrdVectorsLikeTheEnuOneRotatesFlu) {
  // For any attitude, R_ned_frd * FluToFrd(v) must equal EnuToNed(R_enu_flu * v).
  const double angles[][3] = {{0.3, -0.2, 1.1}, {-1.0, 0.5, -2.5}, {0.0, 1.2, 0.4}};
  for (const auto& a : angles) {
    const Quat roll{std::cos(a[0] / 2), std::sin(a[0] / 2), 0, 0};
    const Quat pitch{std::cos(a[1] / 2), 0, std::sin(a[1] / 2), 0};
    const Quat q = Multiply(YawQuat(a[2]), Multiply(pitch, roll));
    const Vec3d v{0.7, -1.3, 2.1};
    const Vec3d expected = EnuToNed(Rotate(q, v));
    const Vec3d got = Rotate(EnuFluToNedFrd(q), FluToFrd(v));
    EXPECT_NEAR(got.x, expected.x, 1e-12);
    EXPECT_NEAR(got.y, expected.y, 1e-12);
    EXPECT_NEAR(got.z, expected.z, 1e-12);
  }
}

}  // namespace
}  // namespace sitlnet::physics

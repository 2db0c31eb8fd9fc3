// Barometer, magnetometer and GPS models against the cited formulas' published values.
#include "physics_mujoco/sensor_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

namespace sitlnet::physics {
namespace {

// Geometric altitude of geopotential altitude H (r0 = 6356766 m, U.S. Standard Atmosphere 1976).
double GeometricOf(double geopotential_m) {
  return 6356766.0 * geopotential_m / (6356766.0 - geopotential_m);
}

TEST(IsaTest, MatchesTheStandardAtmosphereTables) {
  // U.S. Standard Atmosphere 1976, Table I (geopotential altitude): sea level 101325 Pa and
  // 288.15 K; 1000 m 89874.6 Pa, 281.65 K; 5000 m 54019.9 Pa, 255.65 K; the tropopause at
  // 11000 m 22632.1 Pa, 216.65 K (ICAO's 226.32 hPa).
  const struct {
    double geopotential_m, pressure_pa, temperature_k;
  } rows[] = {{0, 101325, 288.15},
              {1000, 89874.6, 281.65},
              {5000, 54019.9, 255.65},
              {11000, 22632.1, 216.65}};
  for (const auto& row : rows) {
    const Atmosphere air = IsaTroposphere(GeometricOf(row.geopotential_m));
    EXPECT_NEAR(air.pressure_pa, row.pressure_pa, 0.1) << row.geopotential_m;
    EXPECT_NEAR(air.temperature_k, row.temperature_k, 1e-6) << row.geopotential_m;
    EXPECT_NEAR(IsaPressureAltitudeM(row.pressure_pa), row.geopotential_m, 0.02);
  }
}

TEST(MagneticFieldTest, ComponentsMatchTheWorldMagneticModel) {
  // WMM2025 at the default origin on 2026-01-01 (evaluated with the npm package geomagnetism
  // 0.2.0, an implementation of NOAA's model): X 21523.1 nT, Y 1334.0 nT, Z 43290.0 nT;
  // the scenario's defaults are its D, I, F rounded to 3 decimals (error < 1e-5 gauss).
  const Vec3d ned = MagneticFieldNedGauss(proto::MagneticField{});
  EXPECT_NEAR(ned.x, 0.215231, 2e-5);
  EXPECT_NEAR(ned.y, 0.013340, 2e-5);
  EXPECT_NEAR(ned.z, 0.432900, 2e-5);
}

class HilSensorModelTest : public ::testing::Test {
 protected:
  HilSensorModel Model(const proto::Robot& robot, int index = 0, uint64_t seed = 1) {
    return HilSensorModel(robot, origin_, &frame_, seed, index);
  }
  proto::GeodeticOrigin origin_;
  GeodeticFrame frame_{origin_};
  Vec3d field_ = MagneticFieldNedGauss(origin_.magnetic_field());
};

// Noise 0: the exact readings.
proto::Robot Exact() {
  proto::Robot robot;
  robot.mutable_barometer()->set_noise_pa(0);
  robot.mutable_magnetometer()->set_noise_gauss(0);
  return robot;
}

TEST_F(HilSensorModelTest, MagnetometerReadsTheFieldInTheBodyFrame) {
  HilSensorModel model = Model(Exact());
  // Level, nose east (ENU yaw 0): forward = east, right = south, down = down.
  const Vec3d east_facing = model.Magnetometer({1, 0, 0, 0});
  EXPECT_NEAR(east_facing.x, field_.y, 1e-12);
  EXPECT_NEAR(east_facing.y, -field_.x, 1e-12);
  EXPECT_NEAR(east_facing.z, field_.z, 1e-12);
  // Nose north (ENU yaw +90 deg): FRD = NED.
  const double h = std::numbers::sqrt2 / 2;
  const Vec3d north_facing = model.Magnetometer({h, 0, 0, h});
  EXPECT_NEAR(north_facing.x, field_.x, 1e-12);
  EXPECT_NEAR(north_facing.y, field_.y, 1e-12);
  EXPECT_NEAR(north_facing.z, field_.z, 1e-12);
  // Upside down about the nose (roll 180 deg, nose east): right = north, down = up.
  const Vec3d inverted = model.Magnetometer({0, 1, 0, 0});
  EXPECT_NEAR(inverted.x, field_.y, 1e-12);
  EXPECT_NEAR(inverted.y, field_.x, 1e-12);
  EXPECT_NEAR(inverted.z, -field_.z, 1e-12);
}

TEST_F(HilSensorModelTest, BarometerAtTheRobotsAltitude) {
  HilSensorModel model = Model(Exact());
  const BarometerSample sample = model.Barometer(12);
  const Atmosphere air = IsaTroposphere(488 + 12);
  EXPECT_DOUBLE_EQ(sample.pressure_hpa, air.pressure_pa / 100);
  EXPECT_NEAR(sample.temperature_degc, air.temperature_k - 273.15, 1e-12);
  // Pressure altitude is geopotential: 500 m geometric is 499.96 m geopotential.
  EXPECT_NEAR(sample.pressure_altitude_m, 500 * 6356766.0 / (6356766.0 + 500), 1e-6);
}

TEST_F(HilSensorModelTest, GpsFixIsThePoseAtItsRate) {
  HilSensorModel model = Model(proto::Robot{});  // 10 Hz
  RobotPose pose;
  pose.position_m = {100, 0, 5};
  pose.velocity_m_s = {1, 2, 3};
  ASSERT_TRUE(model.GpsDue(0));
  const GpsFix fix = model.Gps(0, pose);
  const GeodeticPoint expected = frame_.ToGeodetic(pose.position_m);
  EXPECT_DOUBLE_EQ(fix.position.latitude_deg, expected.latitude_deg);
  EXPECT_DOUBLE_EQ(fix.position.longitude_deg, expected.longitude_deg);
  EXPECT_DOUBLE_EQ(fix.position.altitude_m, 493);
  EXPECT_DOUBLE_EQ(fix.velocity_ned_m_s.x, 2);
  EXPECT_DOUBLE_EQ(fix.velocity_ned_m_s.y, 1);
  EXPECT_DOUBLE_EQ(fix.velocity_ned_m_s.z, -3);
  EXPECT_EQ(fix.satellites, 10);
  // 3 ms steps over one second: fixes at the first step at or after 0, 100, ..., 900 ms.
  std::vector<TimeNs> fixes = {0};
  for (TimeNs t = 3 * kNsPerMs; t < kNsPerS; t += 3 * kNsPerMs) {
    if (model.GpsDue(t)) {
      model.Gps(t, pose);
      fixes.push_back(t);
    }
  }
  ASSERT_EQ(fixes.size(), 10u);
  for (size_t i = 1; i < fixes.size(); ++i) {
    const TimeNs grid = static_cast<TimeNs>(i) * 100 * kNsPerMs;
    EXPECT_GE(fixes[i], grid);
    EXPECT_LT(fixes[i], grid + 3 * kNsPerMs);
  }
}

// The receiver's latency: each fix is of the pose at its sample instant (0, 100, 200 ms, ...)
// and is delivered at the first step at or after that instant + delay_ms (110 ms by default),
// in order; with delay 0 at the instant itself.
TEST_F(HilSensorModelTest, GpsFixesAreDeliveredTheirDelayAfterTheyWereTaken) {
  for (const double delay_ms : {110.0, 0.0}) {
    proto::Robot robot;
    if (delay_ms == 0) robot.mutable_gps()->set_delay_ms(0);
    HilSensorModel model = Model(robot);
    std::vector<std::pair<TimeNs, GpsFix>> delivered;
    for (TimeNs t = 0; t < kNsPerS; t += 4 * kNsPerMs) {
      RobotPose pose;
      pose.position_m = {static_cast<double>(t) / kNsPerS, 0, 0};  // 1 m/s east: x = t
      if (const std::optional<GpsFix> fix = model.DeliveredGps(t, pose)) {
        delivered.emplace_back(t, *fix);
      }
    }
    const size_t expected = delay_ms == 0 ? 10 : 9;  // 0 .. 900 ms; the last 1 or 0 in flight
    ASSERT_EQ(delivered.size(), expected) << delay_ms;
    for (size_t i = 0; i < delivered.size(); ++i) {
      const auto& [t, fix] = delivered[i];
      const TimeNs sampled = static_cast<TimeNs>(i) * 100 * kNsPerMs;
      EXPECT_EQ(fix.sampled_ns, sampled) << delay_ms;
      const TimeNs due = sampled + std::llround(delay_ms * kNsPerMs);
      EXPECT_GE(t, due) << delay_ms;
      EXPECT_LT(t, due + 4 * kNsPerMs) << delay_ms;
      const GeodeticPoint where = frame_.ToGeodetic({static_cast<double>(sampled) / kNsPerS, 0, 0});
      EXPECT_DOUBLE_EQ(fix.position.longitude_deg, where.longitude_deg) << delay_ms;
    }
  }
}

TEST_F(HilSensorModelTest, NoiseHasItsSigmaAndIsSeededPerRobotAndSensor) {
  proto::Robot robot = Exact();
  robot.mutable_gps()->set_horizontal_noise_m(2);
  robot.mutable_barometer()->set_noise_pa(3);
  HilSensorModel model = Model(robot);
  const int samples = 20000;
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < samples; ++i) {
    const double error_pa = model.Barometer(0).pressure_hpa * 100 - IsaTroposphere(488).pressure_pa;
    sum += error_pa;
    sum_sq += error_pa * error_pa;
  }
  // Standard error of the sample sigma: 3 / sqrt(2 * 20000) = 0.015 Pa.
  EXPECT_NEAR(std::sqrt(sum_sq / samples - (sum / samples) * (sum / samples)), 3, 0.06);
  EXPECT_NEAR(sum / samples, 0, 0.1);

  // Same seed and robot: same readings; another robot: others. The magnetometer has no noise,
  // so its readings are exact whatever the other sensors draw.
  HilSensorModel a = Model(robot, 0), b = Model(robot, 0), c = Model(robot, 1);
  const RobotPose pose;
  const double a_lat = a.Gps(0, pose).position.latitude_deg;
  EXPECT_EQ(a_lat, b.Gps(0, pose).position.latitude_deg);
  EXPECT_NE(a_lat, c.Gps(0, pose).position.latitude_deg);
  EXPECT_NEAR(a.Magnetometer({1, 0, 0, 0}).x, field_.y, 1e-12);
  a.Reset();
  EXPECT_EQ(a.Gps(0, pose).position.latitude_deg, a_lat);
}

}  // namespace
}  // namespace sitlnet::physics

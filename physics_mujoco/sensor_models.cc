#include "physics_mujoco/sensor_models.h"

#include <cmath>
#include <numbers>

#include "physics_mujoco/frames.h"

namespace sitlnet::physics {
namespace {

// ISA constants (U.S. Standard Atmosphere 1976, tables 1 and 4).
constexpr double kSeaLevelPressurePa = 101325;
constexpr double kSeaLevelTemperatureK = 288.15;
constexpr double kLapseRateKPerM = 0.0065;
// g0 M0 / (R* L) = 9.80665 * 0.0289644 / (8.31432 * 0.0065).
constexpr double kPressureExponent = 5.25588;
constexpr double kEarthRadiusForGeopotentialM = 6356766;

constexpr double kDegToRad = std::numbers::pi / 180;

// Stream tags: each sensor of each robot has its own generator.
enum SensorTag : uint32_t { kMagTag = 0x6d6167, kBaroTag = 0x62617a, kGpsTag = 0x677073 };

void Seed(std::mt19937_64* engine, uint64_t scenario_seed, int robot_index, SensorTag tag) {
  std::seed_seq seed{static_cast<uint32_t>(scenario_seed),
                     static_cast<uint32_t>(scenario_seed >> 32), static_cast<uint32_t>(robot_index),
                     static_cast<uint32_t>(tag)};
  engine->seed(seed);
}

double Noise(std::mt19937_64* engine, double sigma) {
  if (sigma == 0) return 0;
  return std::normal_distribution<double>(0.0, sigma)(*engine);
}

Quat Conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

}  // namespace

Atmosphere IsaTroposphere(double altitude_msl_m) {
  const double geopotential_m = kEarthRadiusForGeopotentialM * altitude_msl_m /
                                (kEarthRadiusForGeopotentialM + altitude_msl_m);
  Atmosphere air;
  air.temperature_k = kSeaLevelTemperatureK - kLapseRateKPerM * geopotential_m;
  air.pressure_pa =
      kSeaLevelPressurePa * std::pow(air.temperature_k / kSeaLevelTemperatureK, kPressureExponent);
  return air;
}

double IsaPressureAltitudeM(double pressure_pa) {
  return kSeaLevelTemperatureK / kLapseRateKPerM *
         (1 - std::pow(pressure_pa / kSeaLevelPressurePa, 1 / kPressureExponent));
}

Vec3d MagneticFieldNedGauss(const proto::MagneticField& field) {
  const double declination = field.declination_deg() * kDegToRad;
  const double inclination = field.inclination_deg() * kDegToRad;
  const double horizontal = field.intensity_gauss() * std::cos(inclination);
  return {horizontal * std::cos(declination), horizontal * std::sin(declination),
          field.intensity_gauss() * std::sin(inclination)};
}

HilSensorModel::HilSensorModel(const proto::Robot& robot, const proto::GeodeticOrigin& origin,
                               const GeodeticFrame* frame, uint64_t scenario_seed, int robot_index)
    : spec_(robot),
      frame_(frame),
      field_ned_gauss_(MagneticFieldNedGauss(origin.magnetic_field())),
      scenario_seed_(scenario_seed),
      robot_index_(robot_index),
      gps_period_ns_(std::llround(kNsPerS / robot.gps().rate_hz())),
      gps_delay_ns_(std::llround(robot.gps().delay_ms() * kNsPerMs)) {
  SITLNET_DEMAND(frame_ != nullptr && gps_period_ns_ > 0 && gps_delay_ns_ >= 0);
  Reset();
}

void HilSensorModel::Reset() {
  Seed(&mag_engine_, scenario_seed_, robot_index_, kMagTag);
  Seed(&baro_engine_, scenario_seed_, robot_index_, kBaroTag);
  Seed(&gps_engine_, scenario_seed_, robot_index_, kGpsTag);
  next_gps_ns_ = 0;
  gps_in_flight_.clear();
}

Vec3d HilSensorModel::Magnetometer(const Quat& q_enu_flu) {
  // World NED -> body FRD: the inverse of the attitude q_ned_frd.
  Vec3d body = Rotate(Conjugate(EnuFluToNedFrd(q_enu_flu)), field_ned_gauss_);
  const double sigma = spec_.magnetometer().noise_gauss();
  body.x += Noise(&mag_engine_, sigma);
  body.y += Noise(&mag_engine_, sigma);
  body.z += Noise(&mag_engine_, sigma);
  return body;
}

BarometerSample HilSensorModel::Barometer(double z_m) {
  const Atmosphere air = IsaTroposphere(frame_->origin().altitude_m + z_m);
  const double pressure_pa = air.pressure_pa + Noise(&baro_engine_, spec_.barometer().noise_pa());
  return {pressure_pa / 100, IsaPressureAltitudeM(pressure_pa), air.temperature_k - 273.15};
}

GpsFix HilSensorModel::Gps(TimeNs time_ns, const RobotPose& pose) {
  // Fixes stay on the grid 0, T, 2T, ... however the caller's steps fall on it: the next is the
  // first grid instant after `time_ns`.
  next_gps_ns_ += gps_period_ns_ * ((time_ns - next_gps_ns_) / gps_period_ns_ + 1);
  const proto::Gps& gps = spec_.gps();
  Vec3d position = pose.position_m;
  position.x += Noise(&gps_engine_, gps.horizontal_noise_m());
  position.y += Noise(&gps_engine_, gps.horizontal_noise_m());
  position.z += Noise(&gps_engine_, gps.vertical_noise_m());
  Vec3d velocity = EnuToNed(pose.velocity_m_s);
  velocity.x += Noise(&gps_engine_, gps.velocity_noise_m_s());
  velocity.y += Noise(&gps_engine_, gps.velocity_noise_m_s());
  velocity.z += Noise(&gps_engine_, gps.velocity_noise_m_s());
  return {time_ns, frame_->ToGeodetic(position), velocity, static_cast<uint8_t>(gps.satellites())};
}

std::optional<GpsFix> HilSensorModel::DeliveredGps(TimeNs time_ns, const RobotPose& pose) {
  if (GpsDue(time_ns)) gps_in_flight_.push_back(Gps(time_ns, pose));
  if (gps_in_flight_.empty() || gps_in_flight_.front().sampled_ns + gps_delay_ns_ > time_ns) {
    return std::nullopt;
  }
  GpsFix fix = gps_in_flight_.front();
  gps_in_flight_.pop_front();
  return fix;
}

}  // namespace sitlnet::physics

#include "physics_mujoco/px4_messages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "physics_mujoco/frames.h"

namespace sitlnet::physics {
namespace {

constexpr double kStandardGravity_m_s2 = 9.80665;  // g0 of MAVLink's mG unit (CGPM 1901)

int32_t DegE7(double degrees) { return static_cast<int32_t>(std::llround(degrees * 1e7)); }
int32_t Millimetres(double metres) { return static_cast<int32_t>(std::llround(metres * 1e3)); }

int16_t ClampedInt16(double value) {
  return static_cast<int16_t>(std::clamp(std::round(value), -32767.0, 32767.0));
}
uint16_t ClampedUint16(double value) {
  return static_cast<uint16_t>(std::clamp(std::round(value), 0.0, 65534.0));  // 65535: unknown
}

}  // namespace

uint64_t TimeUsec(TimeNs time_ns) { return static_cast<uint64_t>(time_ns / kNsPerUs); }

mavlink::HilSensor MakeHilSensor(TimeNs time_ns, const ImuSample& imu, const Vec3d& mag_frd_gauss,
                                 const BarometerSample& baro) {
  const Vec3d accel = FluToFrd(imu.accel_m_s2);
  const Vec3d gyro = FluToFrd(imu.gyro_rad_s);
  mavlink::HilSensor m;
  m.time_usec = TimeUsec(time_ns);
  m.xacc = static_cast<float>(accel.x);
  m.yacc = static_cast<float>(accel.y);
  m.zacc = static_cast<float>(accel.z);
  m.xgyro = static_cast<float>(gyro.x);
  m.ygyro = static_cast<float>(gyro.y);
  m.zgyro = static_cast<float>(gyro.z);
  m.xmag = static_cast<float>(mag_frd_gauss.x);
  m.ymag = static_cast<float>(mag_frd_gauss.y);
  m.zmag = static_cast<float>(mag_frd_gauss.z);
  m.abs_pressure = static_cast<float>(baro.pressure_hpa);
  m.diff_pressure = 0;
  m.pressure_alt = static_cast<float>(baro.pressure_altitude_m);
  m.temperature = static_cast<float>(baro.temperature_degc);
  m.fields_updated =
      mavlink::kSensorUpdatedAccelGyro | mavlink::kSensorUpdatedMag | mavlink::kSensorUpdatedBaro;
  m.id = 0;
  return m;
}

mavlink::HilGps MakeHilGps(TimeNs time_ns, const GpsFix& fix, const proto::Gps& spec) {
  mavlink::HilGps m;
  m.time_usec = TimeUsec(time_ns);
  m.fix_type = 3;
  m.lat = DegE7(fix.position.latitude_deg);
  m.lon = DegE7(fix.position.longitude_deg);
  m.alt = Millimetres(fix.position.altitude_m);
  m.eph = ClampedUint16(100 * std::max(1.0, spec.horizontal_noise_m()));
  m.epv = ClampedUint16(100 * std::max(1.0, spec.vertical_noise_m()));
  const Vec3d& v = fix.velocity_ned_m_s;
  const double ground_speed_m_s = std::hypot(v.x, v.y);
  m.vel = ClampedUint16(ground_speed_m_s * 100);
  m.vn = ClampedInt16(v.x * 100);
  m.ve = ClampedInt16(v.y * 100);
  m.vd = ClampedInt16(v.z * 100);
  if (ground_speed_m_s >= 0.01) {
    double course_deg = std::atan2(v.y, v.x) * 180 / std::numbers::pi;
    if (course_deg < 0) course_deg += 360;
    m.cog = static_cast<uint16_t>(std::llround(course_deg * 100) % 36000);
  }
  m.satellites_visible = fix.satellites;
  return m;
}

mavlink::HilStateQuaternion MakeGroundTruth(TimeNs time_ns, const RobotPose& pose,
                                            const ImuSample& imu, const GeodeticFrame& frame) {
  mavlink::HilStateQuaternion m;
  m.time_usec = TimeUsec(time_ns);
  const Quat q = EnuFluToNedFrd(pose.orientation);
  m.attitude_quaternion = {static_cast<float>(q.w), static_cast<float>(q.x),
                           static_cast<float>(q.y), static_cast<float>(q.z)};
  const Vec3d rates = FluToFrd(pose.angular_velocity_rad_s);
  m.rollspeed = static_cast<float>(rates.x);
  m.pitchspeed = static_cast<float>(rates.y);
  m.yawspeed = static_cast<float>(rates.z);
  const GeodeticPoint where = frame.ToGeodetic(pose.position_m);
  m.lat = DegE7(where.latitude_deg);
  m.lon = DegE7(where.longitude_deg);
  m.alt = Millimetres(where.altitude_m);
  const Vec3d v = EnuToNed(pose.velocity_m_s);
  m.vx = ClampedInt16(v.x * 100);
  m.vy = ClampedInt16(v.y * 100);
  m.vz = ClampedInt16(v.z * 100);
  const double speed_cm_s = std::hypot(v.x, v.y, v.z) * 100;
  m.ind_airspeed = ClampedUint16(speed_cm_s);
  m.true_airspeed = ClampedUint16(speed_cm_s);
  const Vec3d accel = FluToFrd(imu.accel_m_s2);
  m.xacc = ClampedInt16(accel.x / kStandardGravity_m_s2 * 1000);
  m.yacc = ClampedInt16(accel.y / kStandardGravity_m_s2 * 1000);
  m.zacc = ClampedInt16(accel.z / kStandardGravity_m_s2 * 1000);
  return m;
}

std::optional<RotorSpeeds> RotorSpeedsOf(const mavlink::HilActuatorControls& controls,
                                         double max_speed_rad_s) {
  RotorSpeeds speeds{};
  const bool armed = (controls.mode & mavlink::kModeFlagSafetyArmed) != 0;
  for (int i = 0; i < kRotors; ++i) {
    if (!std::isfinite(controls.controls[i])) return std::nullopt;
    if (armed) speeds[i] = std::clamp(double{controls.controls[i]}, 0.0, 1.0) * max_speed_rad_s;
  }
  return speeds;
}

}  // namespace sitlnet::physics

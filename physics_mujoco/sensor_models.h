// Sensors of the autopilot interfaces besides the IMU (docs/autopilots.md, "Sensors"): the ISA
// barometer, a magnetometer in a constant Earth field, and a GPS receiver, each with white
// Gaussian noise from the robot's own seeded generators.
#ifndef SITLNET_PHYSICS_MUJOCO_SENSOR_MODELS_H_
#define SITLNET_PHYSICS_MUJOCO_SENSOR_MODELS_H_

#include <cstdint>
#include <deque>
#include <optional>
#include <random>

#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

//------------------------------- ISA atmosphere -------------------------------

// Static pressure and temperature of the International Standard Atmosphere.
struct Atmosphere {
  double pressure_pa = 0;
  double temperature_k = 0;
};

// The ISA troposphere (ISO 2533:1975, ICAO Doc 7488, U.S. Standard Atmosphere 1976) at a
// geometric altitude above mean sea level: geopotential altitude H = r0 h / (r0 + h) with
// r0 = 6356766 m; T = 288.15 K - 0.0065 K/m * H; p = 101325 Pa * (T / 288.15 K)^5.25588
// (the exponent is g0 M / (R* L)). Valid below 11 km geopotential.
Atmosphere IsaTroposphere(double altitude_msl_m);
// Pressure altitude: the geopotential altitude at which the ISA troposphere has `pressure_pa`.
double IsaPressureAltitudeM(double pressure_pa);

//------------------------------ Magnetic field ------------------------------

// Earth's field at the origin in world NED (gauss) from declination D, inclination I and total
// intensity F, as the World Magnetic Model defines them: H = F cos I, north = H cos D,
// east = H sin D, down = F sin I.
Vec3d MagneticFieldNedGauss(const proto::MagneticField& field);

//------------------------------ Sensor readings -----------------------------

struct BarometerSample {
  double pressure_hpa = 0;
  double pressure_altitude_m = 0;  // Of the noisy pressure.
  double temperature_degc = 0;
};

struct GpsFix {
  TimeNs sampled_ns = 0;  // When the receiver measured it.
  GeodeticPoint position;
  Vec3d velocity_ned_m_s;
  uint8_t satellites = 0;
};

// The barometer, magnetometer and GPS of one robot. Each sensor draws from its own generator,
// seeded from (scenario seed, robot index, sensor), so enabling one sensor's noise leaves the
// others' readings unchanged; zero noise draws nothing. `frame` must outlive the model.
class HilSensorModel {
 public:
  HilSensorModel(const proto::Robot& robot, const proto::GeodeticOrigin& origin,
                 const GeodeticFrame* frame, uint64_t scenario_seed, int robot_index);

  // Field in the body FRD frame (gauss) for the attitude `q_enu_flu`, plus noise.
  Vec3d Magnetometer(const Quat& q_enu_flu);
  // Pressure at the robot's altitude (origin altitude + z), plus noise.
  BarometerSample Barometer(double z_m);
  // True when a GPS fix is due at virtual time `time_ns` (the first at time 0, then one every
  // 1 / rate_hz); a due fix must be taken with Gps() before asking again.
  bool GpsDue(TimeNs time_ns) const { return time_ns >= next_gps_ns_; }
  // The fix of `pose` at `time_ns` (noise added), and schedules the next.
  GpsFix Gps(TimeNs time_ns, const RobotPose& pose);
  // The receiver with its latency, for a caller that steps through time: takes a fix of `pose`
  // when one is due, and returns the oldest fix taken whose delivery (its sample time +
  // delay_ms) has come by `time_ns`, if any. Fixes are delivered in order, one per call.
  std::optional<GpsFix> DeliveredGps(TimeNs time_ns, const RobotPose& pose);
  // Back to the state after construction (a restarted autopilot gets the same readings).
  void Reset();

 private:
  proto::Robot spec_;
  const GeodeticFrame* frame_;
  Vec3d field_ned_gauss_;
  uint64_t scenario_seed_;
  int robot_index_;
  TimeNs gps_period_ns_;
  TimeNs gps_delay_ns_;
  TimeNs next_gps_ns_ = 0;
  std::deque<GpsFix> gps_in_flight_;  // Taken, not yet delivered, oldest first.
  std::mt19937_64 mag_engine_, baro_engine_, gps_engine_;
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_SENSOR_MODELS_H_

// What sitlnet's physics and sensor models become in PX4's simulator messages, and what PX4's
// actuator outputs become in sitlnet (docs/autopilots.md, "PX4 simulator interface").
#ifndef SITLNET_PHYSICS_MUJOCO_PX4_MESSAGES_H_
#define SITLNET_PHYSICS_MUJOCO_PX4_MESSAGES_H_

#include "mavlink/mavlink.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/sensor_models.h"

namespace sitlnet::physics {

// MAVLink's time_usec of virtual time `time_ns` (whole microseconds, rounded down).
uint64_t TimeUsec(TimeNs time_ns);

// HIL_SENSOR: IMU (body FLU -> FRD), magnetometer (FRD), barometer; fields_updated marks
// accelerometer, gyro, magnetometer and barometer (no differential pressure: no airspeed
// sensor); sensor id 0, the one PX4 takes its lock-step clock from.
mavlink::HilSensor MakeHilSensor(TimeNs time_ns, const ImuSample& imu, const Vec3d& mag_frd_gauss,
                                 const BarometerSample& baro);

// HIL_GPS: 3D fix; eph/epv 100 x max(1 m, noise sigma) (PX4 reads them as accuracy in cm);
// ground speed and course over ground (unknown below 1 cm/s); velocities clamped to int16 cm/s.
mavlink::HilGps MakeHilGps(TimeNs time_ns, const GpsFix& fix, const proto::Gps& spec);

// HIL_STATE_QUATERNION (ground truth): attitude NED/FRD, body rates FRD, true position and
// NED velocity, speed as airspeed (no wind), accelerometer in mG (g0 = 9.80665 m/s^2).
mavlink::HilStateQuaternion MakeGroundTruth(TimeNs time_ns, const RobotPose& pose,
                                            const ImuSample& imu, const GeodeticFrame& frame);

// PX4's motor outputs 0..1 (controls[0..3], PX4's quad-X order = sitlnet's rotor order) to rotor
// speeds u * max_speed when armed (mode has MAV_MODE_FLAG_SAFETY_ARMED), all 0 when not. Values
// outside [0, 1] are clamped. nullopt if a motor output is not finite.
std::optional<RotorSpeeds> RotorSpeedsOf(const mavlink::HilActuatorControls& controls,
                                         double max_speed_rad_s);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_PX4_MESSAGES_H_

// Frame conversions between sitlnet's world ENU / body FLU and ArduPilot's NED / FRD.
#ifndef SITLNET_PHYSICS_MUJOCO_FRAMES_H_
#define SITLNET_PHYSICS_MUJOCO_FRAMES_H_

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

// World vectors: (east, north, up) -> (north, east, down).
Vec3d EnuToNed(const Vec3d& enu);
// Body vectors: (forward, left, up) -> (forward, right, down).
Vec3d FluToFrd(const Vec3d& flu);
// Attitude of body FLU in world ENU -> attitude of body FRD in world NED (w, x, y, z):
// q_ned_frd = q_ned_enu * q_enu_flu * q_flu_frd.
Quat EnuFluToNedFrd(const Quat& q_enu_flu);

Quat Multiply(const Quat& a, const Quat& b);
// Rotates body vector v into the world frame by q.
Vec3d Rotate(const Quat& q, const Vec3d& v);
// Yaw (rad) of the body x axis in the world frame, atan2(y, x) of R * (1, 0, 0).
double YawRad(const Quat& q);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_FRAMES_H_

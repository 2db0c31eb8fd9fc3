#include "physics_mujoco/frames.h"

#include <cmath>
#include <numbers>

namespace sitlnet::physics {

Vec3d EnuToNed(const Vec3d& enu) { return {enu.y, enu.x, -enu.z}; }
Vec3d FluToFrd(const Vec3d& flu) { return {flu.x, -flu.y, -flu.z}; }

Quat Multiply(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Vec3d Rotate(const Quat& q, const Vec3d& v) {
  const Quat p{0, v.x, v.y, v.z};
  const Quat conj{q.w, -q.x, -q.y, -q.z};
  const Quat r = Multiply(Multiply(q, p), conj);
  return {r.x, r.y, r.z};
}

double YawRad(const Quat& q) {
  const Vec3d nose = Rotate(q, {1, 0, 0});
  return std::atan2(nose.y, nose.x);
}

Quat EnuFluToNedFrd(const Quat& q_enu_flu) {
  // ENU -> NED is a half turn about (1, 1, 0)/sqrt(2); FRD -> FLU a half turn about x.
  constexpr double kHalf = std::numbers::sqrt2 / 2;
  const Quat q_ned_enu{0, kHalf, kHalf, 0};
  const Quat q_flu_frd{0, 1, 0, 0};
  Quat q = Multiply(Multiply(q_ned_enu, q_enu_flu), q_flu_frd);
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};  // Same rotation; w >= 0 reads better.
  return q;
}

}  // namespace sitlnet::physics

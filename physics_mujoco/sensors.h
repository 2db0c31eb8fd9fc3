// IMU noise/bias from a seeded generator, and a lidar of horizontal rays cast with mj_ray.
#ifndef SITLNET_PHYSICS_MUJOCO_SENSORS_H_
#define SITLNET_PHYSICS_MUJOCO_SENSORS_H_

#include <mujoco/mujoco.h>

#include <cstdint>
#include <random>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

// Adds white noise and a constant per-axis bias to ideal IMU readings. The bias of each axis
// is drawn once, N(0, bias), from the robot's generator; noise is drawn per sample. With the
// default zero figures no number is drawn and readings are exact.
class ImuNoise {
 public:
  ImuNoise(const proto::Imu& spec, uint64_t scenario_seed, int robot_index);
  void Apply(ImuSample* sample);

 private:
  proto::Imu spec_;
  std::mt19937_64 engine_;
  Vec3d gyro_bias_rad_s_;
  Vec3d accel_bias_m_s2_;
};

// Casts `spec.rays()` rays from `origin` in the body's horizontal plane (rotation `body_to_world`,
// row-major 3x3) against every geom except body `exclude_body`. No hit within range: max range.
void CastLidar(const mjModel* model, const mjData* data, const proto::Lidar& spec,
               const double origin[3], const double body_to_world[9], int exclude_body,
               std::vector<float>* ranges_m);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_SENSORS_H_

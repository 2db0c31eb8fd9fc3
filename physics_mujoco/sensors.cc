#include "physics_mujoco/sensors.h"

#include <cmath>
#include <numbers>

namespace sitlnet::physics {
namespace {

Vec3d DrawBias(std::mt19937_64* engine, double sigma) {
  if (sigma == 0) return {};
  std::normal_distribution<double> normal(0.0, sigma);
  Vec3d bias;
  bias.x = normal(*engine);
  bias.y = normal(*engine);
  bias.z = normal(*engine);
  return bias;
}

void AddNoise(std::mt19937_64* engine, double sigma, const Vec3d& bias, Vec3d* value) {
  value->x += bias.x;
  value->y += bias.y;
  value->z += bias.z;
  if (sigma == 0) return;
  std::normal_distribution<double> normal(0.0, sigma);
  value->x += normal(*engine);
  value->y += normal(*engine);
  value->z += normal(*engine);
}

}  // namespace

ImuNoise::ImuNoise(const proto::Imu& spec, uint64_t scenario_seed, int robot_index) : spec_(spec) {
  // One stream per robot, derived from the scenario seed (docs/architecture.md: one seeded stream
  // per robot, no hidden global stream).
  std::seed_seq seed{static_cast<uint32_t>(scenario_seed),
                     static_cast<uint32_t>(scenario_seed >> 32), static_cast<uint32_t>(robot_index),
                     0x1a4b5u /* "IMU" stream tag */};
  engine_.seed(seed);
  gyro_bias_rad_s_ = DrawBias(&engine_, spec_.gyro_bias_rad_s());
  accel_bias_m_s2_ = DrawBias(&engine_, spec_.accel_bias_m_s2());
}

void ImuNoise::Apply(ImuSample* sample) {
  AddNoise(&engine_, spec_.gyro_noise_rad_s(), gyro_bias_rad_s_, &sample->gyro_rad_s);
  AddNoise(&engine_, spec_.accel_noise_m_s2(), accel_bias_m_s2_, &sample->accel_m_s2);
}

void CastLidar(const mjModel* model, const mjData* data, const proto::Lidar& spec,
               const double origin[3], const double body_to_world[9], int exclude_body,
               std::vector<float>* ranges_m) {
  const int rays = static_cast<int>(spec.rays());
  ranges_m->resize(rays);
  const double max_range_m = spec.max_range_m();
  const double fov_rad = spec.fov_deg() * std::numbers::pi / 180.0;
  for (int i = 0; i < rays; ++i) {
    const double angle = fov_rad * (static_cast<double>(i) / rays - 0.5);
    const double body_dir[3] = {std::cos(angle), std::sin(angle), 0};
    double dir[3];
    mju_mulMatVec(dir, body_to_world, body_dir, 3, 3);
    int geom = -1;
    // flg_static 1: obstacles and ground are static geoms of the world body.
    const double distance = mj_ray(model, data, origin, dir, nullptr, 1, exclude_body, &geom);
    (*ranges_m)[i] =
        static_cast<float>((distance < 0 || distance > max_range_m) ? max_range_m : distance);
  }
}

}  // namespace sitlnet::physics

// MJCF text for the physics world: ground, the scenario's obstacle boxes and multirotors.
#ifndef SITLNET_PHYSICS_MUJOCO_WORLD_BUILDER_H_
#define SITLNET_PHYSICS_MUJOCO_WORLD_BUILDER_H_

#include <array>
#include <string>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "scenario/scenario.h"

namespace sitlnet::physics {

// Name of the multirotor body in every model, and of its IMU site.
inline constexpr char kQuadBodyName[] = "quad";
inline constexpr char kImuSiteName[] = "imu";

// Collision box half-extents of an airframe (metres): body_half_size_m or its default.
std::array<double, 3> BodyHalfSize(const proto::Airframe& airframe);

// A world holding ground, obstacles and ONE multirotor of `airframe` at the origin (placed
// per robot through qpos). Every robot with this airframe shares the compiled model and has
// its own mjData: robots do not collide with each other (docs/physics.md says why).
// `obstacles`: indices into scenario.spec.obstacle() to include, in increasing order (a
// tile's, obstacle_tiles.h); null: every obstacle.
std::string SingleRobotWorldXml(const Scenario& scenario, const proto::Airframe& airframe,
                                Integrator integrator, const std::vector<int>* obstacles = nullptr);

// A world holding every robot of the scenario as bodies of one model, at their start poses.
// Only used to measure the alternative layout (bench/physics).
std::string AllRobotsWorldXml(const Scenario& scenario, Integrator integrator);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_WORLD_BUILDER_H_

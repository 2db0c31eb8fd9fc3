// World: one mjData per robot on a model per airframe and obstacle tile (docs/physics.md,
// "Layout" and "Obstacle culling").
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <set>

#include "physics_mujoco/mujoco_model.h"
#include "physics_mujoco/obstacle_tiles.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/rotor_model.h"
#include "physics_mujoco/sensors.h"
#include "physics_mujoco/step_pool.h"
#include "physics_mujoco/world_builder.h"

namespace sitlnet::physics {

namespace {

// Farthest a robot's centre may move within one physics step while it keeps a tile's model
// (the speed limit below enforces it; faster robots use the model with every obstacle).
// RK4's stages stay within about dt * |v| + dt^2 * |a| of the step's start.
constexpr double kStepTravel_m = 1.0;

// A compiled model: the ground, some obstacles, and one quad of an airframe.
struct CompiledModel {
  ModelPtr model;
  // The same model with sensors off (mjDSBL_SENSOR): for every step but the last of an
  // Advance call. The accelerometer is read only after a call, and sensors never feed back
  // into the dynamics (MuJoCo 2.2.2 mj_forwardSkip), so trajectories and IMU readings are the
  // same; it saves 7 % of an RK4 step and 16 % of an Euler one (docs/performance.md).
  ModelPtr without_sensors;
  int body = -1;  // The quad's body id.
  int obstacles = 0;
};

// Every model of one airframe: one per distinct obstacle set of the tiles visited, and one
// with every obstacle.
struct AirframeModels {
  const proto::Airframe* airframe = nullptr;
  std::string what;  // "file: airframe \"name\"", for errors
  RotorModel rotors;
  std::unique_ptr<CompiledModel> all;
  // Under World::Impl::models_mutex: tiles with the same obstacles share a model, so a robot
  // moving between them keeps its mjData (open ground: the ground-only model everywhere).
  std::map<TileIndex, const CompiledModel*> tiles;
  std::map<std::vector<int>, std::unique_ptr<CompiledModel>> by_obstacles;
};

struct RobotSlot {
  AirframeModels* airframe = nullptr;
  const CompiledModel* model = nullptr;
  bool on_all = true;  // model is airframe->all
  Rect region;         // where the robot keeps a tile model (unused when on_all)
  const RobotPlan* plan = nullptr;
  DataPtr data;
  RotorSpeeds target{};
  RotorSpeeds speeds{};
  int64_t steps = 0;
  double linear_drag_n_s_per_m = 0;
  ImuNoise imu_noise;
  int64_t model_switches = 0;
  bool fixed = false;  // A ground station: no physics.
};

template <typename T>
void CopyArray(T* to, const T* from, int count) {
  if (count > 0) std::memcpy(to, from, sizeof(T) * count);
}

// Moves a robot's state onto a fresh mjData of another model of its airframe: the same bodies,
// joints and sensors, other static obstacle geoms of the world body. Copied: everything
// mj_step reads besides the model (MuJoCo 2.2.2, engine_forward.c: time, qpos, qvel, act,
// qacc_warmstart for the constraint solver, ctrl, qfrc_applied, xfrc_applied, mocap, userdata)
// and the outputs World reads between steps (sensordata: the accelerometer; qacc, act_dot).
// mj_kinematics then gives the obstacles' global poses, which mj_ray reads; every other
// derived quantity is recomputed by the next mj_step before use.
void MoveState(const mjModel* from_m, const mjData* from, const mjModel* to_m, mjData* to) {
  SITLNET_DEMAND(from_m->nq == to_m->nq && from_m->nv == to_m->nv && from_m->na == to_m->na &&
                 from_m->nu == to_m->nu && from_m->nbody == to_m->nbody &&
                 from_m->nmocap == to_m->nmocap && from_m->nuserdata == to_m->nuserdata &&
                 from_m->nsensordata == to_m->nsensordata);
  to->time = from->time;
  CopyArray(to->qpos, from->qpos, to_m->nq);
  CopyArray(to->qvel, from->qvel, to_m->nv);
  CopyArray(to->act, from->act, to_m->na);
  CopyArray(to->qacc_warmstart, from->qacc_warmstart, to_m->nv);
  CopyArray(to->ctrl, from->ctrl, to_m->nu);
  CopyArray(to->qfrc_applied, from->qfrc_applied, to_m->nv);
  CopyArray(to->xfrc_applied, from->xfrc_applied, 6 * to_m->nbody);
  CopyArray(to->mocap_pos, from->mocap_pos, 3 * to_m->nmocap);
  CopyArray(to->mocap_quat, from->mocap_quat, 4 * to_m->nmocap);
  CopyArray(to->userdata, from->userdata, to_m->nuserdata);
  CopyArray(to->sensordata, from->sensordata, to_m->nsensordata);
  CopyArray(to->qacc, from->qacc, to_m->nv);
  CopyArray(to->act_dot, from->act_dot, to_m->na);
  CopyArray(to->warning, from->warning, mjNWARNING);
  mj_kinematics(to_m, to);
  // mj_kinematics normalizes the quaternions in qpos in place; normalizing again at the next
  // step is not exact to the last bit, so the state goes back as it was.
  CopyArray(to->qpos, from->qpos, to_m->nq);
}

}  // namespace

struct World::Impl {
  const Scenario* scenario = nullptr;
  Integrator integrator = Integrator::kRk4;
  std::optional<ObstacleTiles> tiles;  // empty: culling off, every robot on its `all` model
  double max_speed_m_s = 0;            // faster: the `all` model (kStepTravel_m per step)
  std::map<std::string, std::unique_ptr<AirframeModels>> models;  // by airframe name
  mutable std::mutex models_mutex;  // tile models are compiled while robots step in threads
  int models_compiled = 0;
  std::vector<std::unique_ptr<RobotSlot>> robots;  // The simulated robots, ascending.
  std::vector<int> indices;                          // Their global indices.
  std::vector<int> slot_of;  // Per scenario robot: its place in `robots`, or -1.
  StepPool pool;

  explicit Impl(int threads) : pool(std::max(1, threads)) {}

  RobotSlot& Robot(int index) {
    SITLNET_DEMAND(index >= 0 && index < static_cast<int>(slot_of.size()) && slot_of[index] >= 0);
    return *robots[slot_of[index]];
  }

  std::unique_ptr<CompiledModel> Compile(const AirframeModels& am,
                                         const std::vector<int>* obstacles) {
    ModelPtr compiled = LoadModelFromXml(
        SingleRobotWorldXml(*scenario, *am.airframe, integrator, obstacles), am.what);
    const int body = mj_name2id(compiled.get(), mjOBJ_BODY, kQuadBodyName);
    SITLNET_DEMAND(body > 0);
    ++models_compiled;
    const int count =
        obstacles ? static_cast<int>(obstacles->size()) : scenario->spec.obstacle_size();
    ModelPtr without_sensors(mj_copyModel(nullptr, compiled.get()));
    SITLNET_DEMAND(without_sensors != nullptr);
    without_sensors->opt.disableflags |= mjDSBL_SENSOR;
    return std::unique_ptr<CompiledModel>(
        new CompiledModel{std::move(compiled), std::move(without_sensors), body, count});
  }

  // The tile's model, compiled on first use and shared by every robot of the airframe and
  // every tile with the same obstacles.
  const CompiledModel* TileModel(AirframeModels* am, TileIndex tile) {
    std::lock_guard<std::mutex> lock(models_mutex);
    const CompiledModel*& model = am->tiles[tile];
    if (!model) {
      std::vector<int> obstacles = tiles->ObstaclesOf(tile);
      if (static_cast<int>(obstacles.size()) == scenario->spec.obstacle_size()) {
        model = am->all.get();
      } else {
        auto& compiled = am->by_obstacles[obstacles];
        if (!compiled) compiled = Compile(*am, &obstacles);
        model = compiled.get();
      }
    }
    return model;
  }

  // The model of a tile without obstacles (the ground alone), compiled on first use.
  const CompiledModel* GroundModel(AirframeModels* am) {
    std::lock_guard<std::mutex> lock(models_mutex);
    auto& compiled = am->by_obstacles[{}];
    if (!compiled) {
      const std::vector<int> none;
      compiled = Compile(*am, &none);
    }
    return compiled.get();
  }

  bool Fast(const mjData* d) const {
    const double v2 = d->qvel[0] * d->qvel[0] + d->qvel[1] * d->qvel[1] + d->qvel[2] * d->qvel[2];
    return !(v2 <= max_speed_m_s * max_speed_m_s);  // NaN: fast
  }

  // Puts the robot on the model its state calls for, if it is not on it: its tile's while it
  // stays in the tile's region and under the speed limit, else the one with every obstacle.
  // Called whenever the state changes outside mj_step and after every step, so between steps
  // every obstacle the robot can touch or see within lidar range is in its model.
  void PlaceModel(RobotSlot* slot) {
    if (!tiles) return;
    const mjData* d = slot->data.get();
    const double x = d->qpos[0], y = d->qpos[1];
    const bool tiled = !Fast(d) && tiles->HasTile(x, y);
    if (tiled ? (!slot->on_all && slot->region.Contains(x, y)) : slot->on_all) return;
    const CompiledModel* next = slot->airframe->all.get();
    if (tiled) {
      const TileIndex tile = tiles->TileOf(x, y);
      next = TileModel(slot->airframe, tile);
      slot->region = tiles->Region(tile);
    }
    slot->on_all = !tiled;
    if (next == slot->model) return;
    DataPtr data(mj_makeData(next->model.get()));
    SITLNET_DEMAND(data != nullptr);
    MoveState(slot->model->model.get(), slot->data.get(), next->model.get(), data.get());
    slot->data = std::move(data);
    slot->model = next;
    ++slot->model_switches;
  }

  // One physics step of one robot: motor lag, rotor wrench from the current attitude, mj_step.
  // `sensors`: evaluate the accelerometer (the last step before anyone can read it).
  void Step(RobotSlot* slot, bool sensors) {
    if (slot->fixed) {  // A ground station: no physics, it stays where it is.
      ++slot->steps;
      return;
    }
    const AirframeModels& am = *slot->airframe;
    am.rotors.StepMotors(slot->target, &slot->speeds);
    ApplyRotorWrench(am.rotors, slot->speeds, slot->linear_drag_n_s_per_m, slot->model->body,
                     slot->data.get());
    const CompiledModel& cm = *slot->model;
    mj_step(sensors ? cm.model.get() : cm.without_sensors.get(), slot->data.get());
    ++slot->steps;
    PlaceModel(slot);
  }

  // Steps `n` robots: robots[i] by its own steps from `listed`, or (listed null) the i-th
  // simulated robot by `steps`. Contiguous chunks, one per thread: each robot's steps run back
  // to back on one core (its mjData stays in that core's cache); no synchronization between
  // steps.
  void StepInChunks(size_t n, const RobotSteps* listed, int steps) {
    // Two robots of a step each are split too: on the critical path of cheap autopilots the
    // second core pays (measured against stepping fewer than 8 robot-steps on the caller alone:
    // docs/performance.md, "The critical path of one iteration").
    const int chunks = std::min(static_cast<int>(n), pool.threads());
    // The task captures one pointer, so the std::function holds it without allocating (an
    // autopilot fleet advances 250-1000 times a virtual second, robot by robot).
    struct Job {
      Impl* impl;
      const RobotSteps* listed;
      int n, chunks, steps;
    } job{this, listed, static_cast<int>(n), chunks, steps};
    pool.Run(chunks, [&job](int chunk) {
      const int begin = job.n * chunk / job.chunks;
      const int end = job.n * (chunk + 1) / job.chunks;
      for (int i = begin; i < end; ++i) {
        RobotSlot* slot = job.listed ? &job.impl->Robot(job.listed[i].robot)
                                     : job.impl->robots[i].get();
        const int steps = job.listed ? job.listed[i].steps : job.steps;
        SITLNET_DEMAND(steps >= 0);
        for (int s = 0; s < steps; ++s) job.impl->Step(slot, s == steps - 1);
      }
    });
  }

  // `steps`: the robot's time afterwards (0 at construction; a reset keeps the world's clock).
  void PlaceAtStart(RobotSlot* slot, int64_t steps) {
    // A fresh mjData on the `all` model, then the start tile's model.
    slot->model = slot->airframe->all.get();
    slot->on_all = true;
    const mjModel* m = slot->model->model.get();
    slot->data.reset(mj_makeData(m));
    SITLNET_DEMAND(slot->data != nullptr);
    mjData* d = slot->data.get();
    const auto& spec = slot->plan->spec;
    d->qpos[0] = spec.position_m().x();
    d->qpos[1] = spec.position_m().y();
    d->qpos[2] = spec.position_m().z();
    const double half_yaw = spec.yaw_deg() * std::numbers::pi / 360.0;
    d->qpos[3] = std::cos(half_yaw);
    d->qpos[4] = 0;
    d->qpos[5] = 0;
    d->qpos[6] = std::sin(half_yaw);
    // Sensors and derived positions valid before the first step.
    mj_forward(m, d);
    slot->target = {};
    slot->speeds = {};
    slot->steps = steps;
    PlaceModel(slot);
  }
};

World::World(const Scenario& scenario, const WorldOptions& options)
    : impl_(std::make_unique<Impl>(options.threads)) {
  Impl& impl = *impl_;
  impl.scenario = &scenario;
  impl.integrator = options.integrator.value_or(scenario.spec.timing().physics_integrator() ==
                                                        proto::Timing::INTEGRATOR_EULER
                                                    ? Integrator::kEuler
                                                    : Integrator::kRk4);
  if (options.cull_obstacles) {
    // Reach: the longest lidar ray, or the body's bounding sphere plus one step's travel. Over
    // every robot of the scenario, simulated or not: each node host cuts the same tiles.
    double reach_m = 0;
    for (const RobotPlan& plan : scenario.robots) {
      const auto half = BodyHalfSize(plan.airframe);
      const double lidar_m = plan.spec.lidar().rays() > 0 ? plan.spec.lidar().max_range_m() : 0;
      reach_m = std::max({reach_m, lidar_m, std::hypot(half[0], half[1], half[2]) + kStepTravel_m});
    }
    SITLNET_DEMAND(options.cull_tile_m > 0);
    impl.tiles.emplace(scenario, options.cull_tile_m, reach_m);
    impl.max_speed_m_s = kStepTravel_m * kNsPerS / static_cast<double>(scenario.physics_step_ns);
  }
  impl.indices = scenario.RobotSlice(options.robots);
  impl.slot_of.assign(scenario.robots.size(), -1);
  for (const int index : impl.indices) {
    const RobotPlan& plan = scenario.robots[index];
    impl.slot_of[index] = static_cast<int>(impl.robots.size());
    auto& am = impl.models[plan.airframe.name()];
    if (!am) {
      am.reset(new AirframeModels{
          &plan.airframe,
          scenario.source_path + ": airframe \"" +
              (plan.airframe.name().empty() ? std::string("default") : plan.airframe.name()) + "\"",
          RotorModel(plan.airframe, scenario.physics_step_ns),
          {},
          {},
          {}});
      // Compiled up front: bad airframes fail here, and it is the fallback of every tile.
      am->all = impl.Compile(*am, nullptr);
    }
    auto slot = std::unique_ptr<RobotSlot>(
        new RobotSlot{am.get(),
                      nullptr,
                      true,
                      {},
                      &plan,
                      nullptr,
                      {},
                      {},
                      0,
                      plan.airframe.linear_drag_n_s_per_m(),
                      ImuNoise(plan.spec.imu(), scenario.spec.timing().seed(), plan.index),
                      0});
    slot->fixed = plan.spec.ground_station();
    impl.PlaceAtStart(slot.get(), 0);
    impl.robots.push_back(std::move(slot));
  }
  // Every tile model compiled now rather than in the step that first needs it: in flight a
  // compile took about 1.4 ms on a stepping thread (0.3 ms here, before the stepping starts),
  // and robots flying side by side reach new tiles in the same step (the 64-robot flight's
  // iteration grew from 5 to 17-24 ms there; in realtime pacing that is a late iteration). The
  // models of the tiles near an obstacle and the ground-only one, for each airframe that flies.
  // Beyond WorldOptions::cull_tiles_compiled_up_front such tiles (docs/physics.md: a long lidar
  // widens every obstacle's surroundings) they are compiled on first use, as before.
  if (impl.tiles && scenario.spec.obstacle_size() > 0) {
    std::set<AirframeModels*> flying;
    for (const auto& slot : impl.robots) {
      if (!slot->fixed) flying.insert(slot->airframe);
    }
    const auto near = impl.tiles->TilesNearObstacles(options.cull_tiles_compiled_up_front);
    for (auto& [name, am] : impl.models) {
      if (!flying.contains(am.get())) continue;
      impl.GroundModel(am.get());
      if (near) {
        for (const TileIndex& tile : *near) impl.TileModel(am.get(), tile);
      }
    }
  }
}

World::~World() = default;

int World::robot_count() const { return static_cast<int>(impl_->robots.size()); }
const std::vector<int>& World::robots() const { return impl_->indices; }
bool World::simulates(int robot) const {
  return robot >= 0 && robot < static_cast<int>(impl_->slot_of.size()) &&
         impl_->slot_of[robot] >= 0;
}
TimeNs World::step_ns() const { return impl_->scenario->physics_step_ns; }
TimeNs World::now_ns() const { return impl_->robots.front()->steps * step_ns(); }
TimeNs World::time_ns(int robot) const { return impl_->Robot(robot).steps * step_ns(); }
int64_t World::steps(int robot) const { return impl_->Robot(robot).steps; }

void World::Advance(int steps) { impl_->StepInChunks(impl_->robots.size(), nullptr, steps); }

void World::Advance(const std::vector<RobotSteps>& robots) {
  impl_->StepInChunks(robots.size(), robots.data(), 0);
}

void World::SetRotorTarget(int robot, const RotorSpeeds& target_rad_s) {
  RobotSlot& slot = impl_->Robot(robot);
  const double max = slot.airframe->rotors.max_speed_rad_s();
  for (int i = 0; i < kRotors; ++i) slot.target[i] = std::clamp(target_rad_s[i], 0.0, max);
}

void World::SetRotorSpeeds(int robot, const RotorSpeeds& speeds_rad_s) {
  SetRotorTarget(robot, speeds_rad_s);
  RobotSlot& slot = impl_->Robot(robot);
  slot.speeds = slot.target;
}

const RotorSpeeds& World::rotor_speeds(int robot) const { return impl_->Robot(robot).speeds; }
const RotorSpeeds& World::rotor_target(int robot) const { return impl_->Robot(robot).target; }

RobotPose World::Pose(int robot) const {
  const mjData* d = impl_->Robot(robot).data.get();
  RobotPose pose;
  pose.position_m = {d->qpos[0], d->qpos[1], d->qpos[2]};
  pose.orientation = {d->qpos[3], d->qpos[4], d->qpos[5], d->qpos[6]};
  // Free joint: linear velocity in the world frame, angular velocity in the body frame.
  pose.velocity_m_s = {d->qvel[0], d->qvel[1], d->qvel[2]};
  pose.angular_velocity_rad_s = {d->qvel[3], d->qvel[4], d->qvel[5]};
  return pose;
}

ImuSample World::Imu(int robot) {
  RobotSlot& slot = impl_->Robot(robot);
  const mjData* d = slot.data.get();
  ImuSample sample;
  sample.gyro_rad_s = {d->qvel[3], d->qvel[4], d->qvel[5]};
  // The accelerometer (site frame = body frame) is evaluated by mj_step's forward pass: the
  // specific force over the last step.
  sample.accel_m_s2 = {d->sensordata[0], d->sensordata[1], d->sensordata[2]};
  slot.imu_noise.Apply(&sample);
  return sample;
}

void World::Lidar(int robot, std::vector<float>* ranges_m) const {
  RobotSlot& slot = impl_->Robot(robot);
  const proto::Lidar& spec = slot.plan->spec.lidar();
  if (spec.rays() == 0) {
    ranges_m->clear();
    return;
  }
  const mjData* d = slot.data.get();
  double rotation[9];
  mju_quat2Mat(rotation, d->qpos + 3);
  // Exact on a tile model too: every obstacle within max_range_m of the robot is in it.
  CastLidar(slot.model->model.get(), d, spec, d->qpos, rotation, slot.model->body, ranges_m);
}

void World::SetVelocity(int robot, const Vec3d& velocity_m_s) {
  RobotSlot& slot = impl_->Robot(robot);
  mjData* d = slot.data.get();
  d->qvel[0] = velocity_m_s.x;
  d->qvel[1] = velocity_m_s.y;
  d->qvel[2] = velocity_m_s.z;
  impl_->PlaceModel(&slot);  // a speed past the limit needs the model with every obstacle
}

void World::ResetRobot(int robot) {
  RobotSlot& slot = impl_->Robot(robot);
  impl_->PlaceAtStart(&slot, slot.steps);
}

const proto::Airframe& World::airframe(int robot) const {
  return impl_->Robot(robot).plan->airframe;
}

int World::obstacles_in_model(int robot) const { return impl_->Robot(robot).model->obstacles; }

int64_t World::model_switches() const {
  int64_t switches = 0;
  for (const auto& slot : impl_->robots) switches += slot->model_switches;
  return switches;
}

int World::models_compiled() const {
  std::lock_guard<std::mutex> lock(impl_->models_mutex);
  return impl_->models_compiled;
}

}  // namespace sitlnet::physics

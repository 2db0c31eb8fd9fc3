// World: one mjData per robot on a shared mjModel per airframe (docs/physics.md, "Layout").
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "physics_mujoco/mujoco_model.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/rotor_model.h"
#include "physics_mujoco/sensors.h"
#include "physics_mujoco/step_pool.h"
#include "physics_mujoco/world_builder.h"

namespace sitlnet::physics {

namespace {

struct AirframeModel {
  ModelPtr model;
  RotorModel rotors;
  int body = -1;  // The quad's body id.
};

struct RobotSlot {
  const AirframeModel* airframe_model = nullptr;
  const RobotPlan* plan = nullptr;
  DataPtr data;
  RotorSpeeds target{};
  RotorSpeeds speeds{};
  int64_t steps = 0;
  bool frame_driven = false;
  double linear_drag_n_s_per_m = 0;
  ImuNoise imu_noise;
};

// One physics step of one robot: motor lag, rotor wrench from the current attitude, mj_step.
void StepRobot(RobotSlot* slot) {
  const AirframeModel& am = *slot->airframe_model;
  am.rotors.StepMotors(slot->target, &slot->speeds);
  ApplyRotorWrench(am.rotors, slot->speeds, slot->linear_drag_n_s_per_m, am.body, slot->data.get());
  mj_step(am.model.get(), slot->data.get());
  ++slot->steps;
}

void PlaceAtStart(RobotSlot* slot) {
  const mjModel* m = slot->airframe_model->model.get();
  mjData* d = slot->data.get();
  mj_resetData(m, d);
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
  slot->steps = 0;
}

}  // namespace

struct World::Impl {
  const Scenario* scenario = nullptr;
  std::map<std::string, std::unique_ptr<AirframeModel>> models;  // by airframe name
  std::vector<std::unique_ptr<RobotSlot>> robots;
  StepPool pool;
  std::vector<RobotSlot*> active;  // scratch: robots stepped by Advance

  explicit Impl(int threads) : pool(std::max(1, threads)) {}

  RobotSlot& Robot(int index) {
    SITLNET_DEMAND(index >= 0 && index < static_cast<int>(robots.size()));
    return *robots[index];
  }
};

World::World(const Scenario& scenario, const WorldOptions& options)
    : impl_(std::make_unique<Impl>(options.threads)) {
  impl_->scenario = &scenario;
  for (const RobotPlan& plan : scenario.robots) {
    auto& model = impl_->models[plan.airframe.name()];
    if (!model) {
      const std::string what =
          scenario.source_path + ": airframe \"" +
          (plan.airframe.name().empty() ? std::string("default") : plan.airframe.name()) + "\"";
      ModelPtr compiled =
          LoadModelFromXml(SingleRobotWorldXml(scenario, plan.airframe, options.integrator), what);
      const int body = mj_name2id(compiled.get(), mjOBJ_BODY, kQuadBodyName);
      SITLNET_DEMAND(body > 0);
      model.reset(new AirframeModel{std::move(compiled),
                                    RotorModel(plan.airframe, scenario.physics_step_ns), body});
    }
    auto slot = std::unique_ptr<RobotSlot>(
        new RobotSlot{model.get(),
                      &plan,
                      DataPtr(mj_makeData(model->model.get())),
                      {},
                      {},
                      0,
                      false,
                      plan.airframe.linear_drag_n_s_per_m(),
                      ImuNoise(plan.spec.imu(), scenario.spec.timing().seed(), plan.index)});
    SITLNET_DEMAND(slot->data != nullptr);
    PlaceAtStart(slot.get());
    impl_->robots.push_back(std::move(slot));
  }
}

World::~World() = default;

int World::robot_count() const { return static_cast<int>(impl_->robots.size()); }
TimeNs World::step_ns() const { return impl_->scenario->physics_step_ns; }
TimeNs World::time_ns(int robot) const { return impl_->Robot(robot).steps * step_ns(); }
int64_t World::steps(int robot) const { return impl_->Robot(robot).steps; }

void World::Advance(int steps) {
  auto& active = impl_->active;
  active.clear();
  for (auto& slot : impl_->robots) {
    if (!slot->frame_driven) active.push_back(slot.get());
  }
  const int n = static_cast<int>(active.size());
  // Contiguous chunks, one per thread: each robot's steps run back to back on one core
  // (its mjData stays in that core's cache); no synchronization between steps.
  const int chunks = std::min(n, impl_->pool.threads());
  impl_->pool.Run(chunks, [&](int chunk) {
    const int begin = n * chunk / chunks;
    const int end = n * (chunk + 1) / chunks;
    for (int i = begin; i < end; ++i) {
      for (int s = 0; s < steps; ++s) StepRobot(active[i]);
    }
  });
}

void World::AdvanceRobot(int robot, int steps) {
  RobotSlot& slot = impl_->Robot(robot);
  for (int s = 0; s < steps; ++s) StepRobot(&slot);
}

void World::SetFrameDriven(int robot, bool frame_driven) {
  impl_->Robot(robot).frame_driven = frame_driven;
}
bool World::frame_driven(int robot) const { return impl_->Robot(robot).frame_driven; }

void World::SetRotorTarget(int robot, const RotorSpeeds& target_rad_s) {
  RobotSlot& slot = impl_->Robot(robot);
  const double max = slot.airframe_model->rotors.max_speed_rad_s();
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
  CastLidar(slot.airframe_model->model.get(), d, spec, d->qpos, rotation, slot.airframe_model->body,
            ranges_m);
}

void World::SetVelocity(int robot, const Vec3d& velocity_m_s) {
  mjData* d = impl_->Robot(robot).data.get();
  d->qvel[0] = velocity_m_s.x;
  d->qvel[1] = velocity_m_s.y;
  d->qvel[2] = velocity_m_s.z;
}

void World::ResetRobot(int robot) { PlaceAtStart(&impl_->Robot(robot)); }

const proto::Airframe& World::airframe(int robot) const {
  return impl_->Robot(robot).plan->airframe;
}

}  // namespace sitlnet::physics

// physics_bench: microseconds per physics step for 1, 16, 64 and 128 quads (issue 5):
//   raw mj_step over one mjData per robot (the models the World builds), 1 and 2 threads;
//   raw mj_step of ONE model holding every robot (the alternative layout);
//   World::Advance (rotor/motor model, wrench, bookkeeping) with 1 and 2 threads;
//   PhysicsServer::Advance (plus polling, failsafe and state timing, no subscribers);
//   then obstacle culling on 64 robots among 16 copies of the case study's arrow (CullingTable).
// Every figure is the median of 9 interleaved runs, all in the same process. Usage:
//   physics_bench [--quick] [--culling]   (--quick: 1 run each, for smoke tests;
//                                          --culling: only the obstacle-culling table)
// The command -> state round trip over a real ctl0 is physics_rtt_bench (needs root).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "physics_mujoco/mujoco_model.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/rotor_model.h"
#include "physics_mujoco/step_pool.h"
#include "physics_mujoco/world_builder.h"

namespace sitlnet::physics {
namespace {

int g_runs = 9;

// N robots on a 2 m grid at 2 m altitude, 4 obstacle boxes around them.
Scenario GridScenario(int robots, int ctl_octet = 78) {
  std::string text = "name: \"bench\"\n";
  const int side = static_cast<int>(std::ceil(std::sqrt(robots)));
  for (int i = 0; i < robots; ++i) {
    text += "robot { name: \"r" + std::to_string(i) +
            "\" position_m { x: " + std::to_string(2 * (i % side)) +
            " y: " + std::to_string(2 * (i / side)) + " z: 2 } }\n";
  }
  const double far = 2.0 * side + 3;
  for (int k = 0; k < 4; ++k) {
    const double x = (k % 2 == 0) ? -3 : far;
    const double y = (k < 2) ? -3 : far;
    text += "obstacle { center_m { x: " + std::to_string(x) + " y: " + std::to_string(y) +
            " z: 5 } size_m { x: 2 y: 3 z: 10 } yaw_deg: 30 }\n";
  }
  text += "addresses { ctl_subnet: \"127." + std::to_string(ctl_octet) +
          ".0.0/16\" physics_port: 39999 }\n";
  return LoadScenarioText(text, "bench");
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

TimeNs ThreadCpuNowNs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return TimeNs{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

// Time of `run(steps)` / steps, in microseconds: this thread's CPU time for single-threaded
// runs (not inflated when other processes take the core), wall time for threaded ones.
template <typename Run>
double UsPerStep(int steps, bool cpu_time, Run run) {
  const TimeNs start = cpu_time ? ThreadCpuNowNs() : MonotonicNowNs();
  run(steps);
  const TimeNs end = cpu_time ? ThreadCpuNowNs() : MonotonicNowNs();
  return static_cast<double>(end - start) / kNsPerUs / steps;
}

// Hover wrench held in xfrc_applied: the raw baselines fly the same trajectory.
void HoldHover(mjData* d, int body, double mass_kg) {
  d->xfrc_applied[6 * body + 2] = mass_kg * 9.81;
}

enum Column { kRaw1, kOneModel, kWorld1, kServer1, kRaw2, kWorld2, kServer2, kColumns };

struct Row {
  int robots;
  const char* integrator;
  double us[kColumns];
};

Row Measure(int robots, Integrator integrator) {
  const Scenario scenario = GridScenario(robots);
  const proto::Airframe& airframe = scenario.robots[0].airframe;
  const double mass = airframe.mass_kg();
  const int steps = std::max(200, 20000 / robots) / 10 * 10;

  // Raw, per-robot mjData on the World's own model.
  ModelPtr model = LoadModelFromXml(SingleRobotWorldXml(scenario, airframe, integrator), "bench");
  const int body = mj_name2id(model.get(), mjOBJ_BODY, kQuadBodyName);
  std::vector<DataPtr> datas;
  for (const RobotPlan& plan : scenario.robots) {
    datas.emplace_back(mj_makeData(model.get()));
    mjData* d = datas.back().get();
    d->qpos[0] = plan.spec.position_m().x();
    d->qpos[1] = plan.spec.position_m().y();
    d->qpos[2] = plan.spec.position_m().z();
    HoldHover(d, body, mass);
  }
  StepPool pool(2);
  // Raw, one model with every robot.
  ModelPtr all = LoadModelFromXml(AllRobotsWorldXml(scenario, integrator), "bench all");
  DataPtr all_data(mj_makeData(all.get()));
  SITLNET_DEMAND(all_data != nullptr);
  for (int i = 0; i < robots; ++i) {
    const int b = mj_name2id(all.get(), mjOBJ_BODY, (kQuadBodyName + std::to_string(i)).c_str());
    HoldHover(all_data.get(), b, mass);
  }
  const double hover = std::sqrt(mass * 9.81 / (4 * airframe.thrust_coefficient()));
  World world1(scenario, WorldOptions{integrator, 1});
  World world2(scenario, WorldOptions{integrator, 2});
  ServerOptions options;
  options.world = WorldOptions{integrator, 1};
  const Scenario scenario_b = GridScenario(robots, 79);  // its own addresses
  PhysicsServer server1(scenario_b, options);
  options.world = WorldOptions{integrator, 2};
  PhysicsServer server(scenario, options);
  for (int i = 0; i < robots; ++i) {
    for (World* world : {&world1, &world2, &server1.world(), &server.world()}) {
      world->SetRotorSpeeds(i, {hover, hover, hover, hover});
    }
  }

  auto raw1 = [&](int k) {
    for (auto& d : datas) {
      for (int s = 0; s < k; ++s) mj_step(model.get(), d.get());
    }
  };
  auto raw2 = [&](int k) {
    const int chunks = std::min(robots, 2);
    pool.Run(chunks, [&](int c) {
      for (int i = robots * c / chunks; i < robots * (c + 1) / chunks; ++i) {
        for (int s = 0; s < k; ++s) mj_step(model.get(), datas[i].get());
      }
    });
  };
  auto one_model = [&](int k) {
    for (int s = 0; s < k; ++s) mj_step(all.get(), all_data.get());
  };
  // World and server advance 10 steps a call: one 10 ms iteration of the default timing.
  auto w1 = [&](int k) {
    for (int s = 0; s < k; s += 10) world1.Advance(10);
  };
  auto w2 = [&](int k) {
    for (int s = 0; s < k; s += 10) world2.Advance(10);
  };
  auto s1 = [&](int k) {
    for (int s = 0; s < k; s += 10) server1.Advance(10);
  };
  auto server2 = [&](int k) {
    for (int s = 0; s < k; s += 10) server.Advance(10);
  };
  std::vector<double> samples[kColumns];
  // Runs interleaved, so that load from other processes hits every column alike.
  for (int r = -1; r < g_runs; ++r) {  // r = -1: warm-up, discarded
    const double us[kColumns] = {UsPerStep(steps, true, raw1),    UsPerStep(steps, true, one_model),
                                 UsPerStep(steps, true, w1),      UsPerStep(steps, true, s1),
                                 UsPerStep(steps, false, raw2),   UsPerStep(steps, false, w2),
                                 UsPerStep(steps, false, server2)};
    if (r < 0) continue;
    for (int c = 0; c < kColumns; ++c) samples[c].push_back(us[c]);
  }
  Row row{robots, integrator == Integrator::kRk4 ? "RK4" : "Euler", {}};
  for (int c = 0; c < kColumns; ++c) row.us[c] = Median(samples[c]);
  return row;
}

// Thread CPU ns per robot-step of the work World adds around mj_step (motor lag + wrench),
// measured alone: the overhead without mj_step's run-to-run noise.
double OwnWorkNsPerRobotStep() {
  const Scenario scenario = GridScenario(64);
  const proto::Airframe& airframe = scenario.robots[0].airframe;
  ModelPtr model =
      LoadModelFromXml(SingleRobotWorldXml(scenario, airframe, Integrator::kRk4), "bench own");
  const RotorModel rotors(airframe, scenario.physics_step_ns);
  std::vector<DataPtr> datas;
  std::vector<RotorSpeeds> speeds(64);
  for (int i = 0; i < 64; ++i) datas.emplace_back(mj_makeData(model.get()));
  const RotorSpeeds target{1000, 1010, 990, 1005};
  std::vector<double> samples;
  const int steps = 2000;
  for (int r = 0; r < g_runs; ++r) {
    const TimeNs start = ThreadCpuNowNs();
    for (int i = 0; i < 64; ++i) {
      for (int s = 0; s < steps; ++s) {
        rotors.StepMotors(target, &speeds[i]);
        ApplyRotorWrench(rotors, speeds[i], 0.1, 1, datas[i].get());
      }
    }
    samples.push_back(static_cast<double>(ThreadCpuNowNs() - start) / (64.0 * steps));
  }
  return Median(samples);
}

// The 64-robot flocking layout of bench/scale/gen_scenario.py: 16 replicas of the case study's
// arrow, read from scenarios/arrow_flocking.textproto (10 boxes each: nine head boxes and the
// shaft), 50 m apart along y, and 36-ray lidars of 15 m. The bench flies no flocker, so each
// replica's 2 x 2 start block (x = 0 and -4) is split into two pairs that fly east at 5 m/s past
// either side of the arrow at 10 m (y = +-18 m from its axis: 4.5 m beside the widest head box),
// as the two subgroups of the case study's shadowed run do; in 10 s they pass the head and the
// shaft's first part, the arrow within lidar reach from x = 8 m on.
Scenario ScaleScenario() {
  const Scenario case_study = LoadScenarioFile(SITLNET_CASE_STUDY_SCENARIO);
  constexpr int kReplicas = 16;
  constexpr double kReplicaPitchM = 50;
  constexpr double kPairOffsetM = 16;  // added to the start block's y = +-2 m
  proto::Scenario spec = case_study.spec;
  spec.set_name("bench");
  spec.clear_robot();
  spec.clear_obstacle();
  for (int r = 0; r < kReplicas; ++r) {
    const double y0 = kReplicaPitchM * (r - (kReplicas - 1) / 2.0);
    for (const proto::Robot& block_robot : case_study.spec.robot()) {
      proto::Robot* robot = spec.add_robot();
      *robot = block_robot;
      robot->set_name("uav" + std::to_string(spec.robot_size()));
      const double y = block_robot.position_m().y();
      robot->mutable_position_m()->set_y(y0 + y + std::copysign(kPairOffsetM, y));
      robot->mutable_position_m()->set_z(10);
    }
    for (const proto::Obstacle& arrow_box : case_study.spec.obstacle()) {
      proto::Obstacle* box = spec.add_obstacle();
      *box = arrow_box;
      box->set_name(arrow_box.name() + "_r" + std::to_string(r));
      box->mutable_center_m()->set_y(arrow_box.center_m().y() + y0);
    }
  }
  spec.mutable_addresses()->set_ctl_subnet("127.80.0.0/16");
  spec.mutable_addresses()->set_physics_port(39999);
  std::string text;
  SITLNET_DEMAND(google::protobuf::TextFormat::PrintToString(spec, &text));
  return LoadScenarioText(text, "bench scale");
}

void CullingTable() {
  const Scenario scenario = ScaleScenario();
  const proto::Airframe& airframe = scenario.robots[0].airframe;
  const double hover = std::sqrt(airframe.mass_kg() * 9.81 / (4 * airframe.thrust_coefficient()));
  const double tiles_m[] = {0, 10, 20, 40, 80};  // 0: no culling
  const int robots = static_cast<int>(scenario.robots.size());
  const int boxes = scenario.spec.obstacle_size();
  std::printf(
      "\nobstacle culling, %d robots of bench/scale (%d boxes) flying east at 5 m/s past the "
      "arrows:\nus per step (all robots), World::Advance(10), 1 thread, thread CPU, median of %d\n",
      robots, boxes, g_runs);
  std::printf("%5s | %10s", "integ", "no_culling");
  for (double tile : tiles_m) {
    if (tile > 0) std::printf("  tile%3.0fm", tile);
  }
  std::printf(" | obstacles per model (tile 20 m), switches, models\n");
  for (Integrator integrator : {Integrator::kRk4, Integrator::kEuler}) {
    std::vector<std::unique_ptr<World>> worlds;
    for (double tile : tiles_m) {
      WorldOptions options{integrator, 1};
      options.cull_obstacles = tile > 0;
      if (tile > 0) options.cull_tile_m = tile;
      worlds.push_back(std::make_unique<World>(scenario, options));
      for (int i = 0; i < robots; ++i) {
        worlds.back()->SetRotorSpeeds(i, {hover, hover, hover, hover});
        worlds.back()->SetVelocity(i, {5, 0, 0});
      }
    }
    std::vector<std::vector<double>> samples(worlds.size());
    std::vector<float> ranges;
    for (int r = -1; r < g_runs; ++r) {
      for (size_t w = 0; w < worlds.size(); ++w) {
        const double us = UsPerStep(1000, true, [&](int k) {
          for (int s = 0; s < k; s += 10) {
            worlds[w]->Advance(10);
            for (int i = 0; i < robots; ++i) worlds[w]->Lidar(i, &ranges);  // as the server: 100 Hz
          }
        });
        if (r >= 0) samples[w].push_back(us);
      }
    }
    std::printf("%5s |", integrator == Integrator::kRk4 ? "RK4" : "Euler");
    for (auto& column : samples) std::printf(" %10.1f", Median(column));
    int most = 0;
    for (int i = 0; i < robots; ++i) most = std::max(most, worlds[2]->obstacles_in_model(i));
    std::printf(" | max %d of %d, %ld, %d\n", most, boxes,
                static_cast<long>(worlds[2]->model_switches()), worlds[2]->models_compiled());
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace sitlnet::physics

int main(int argc, char** argv) {
  using namespace sitlnet::physics;
  bool culling_only = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) {
      g_runs = 1;
    } else if (!std::strcmp(argv[i], "--culling")) {
      culling_only = true;
    } else {
      std::fprintf(
          stderr,
          "physics_bench: unknown argument %s; usage: physics_bench [--quick] [--culling]\n",
          argv[i]);
      return 2;
    }
  }
  if (culling_only) {
    CullingTable();
    return 0;
  }
  std::printf(
      "us per physics step (all robots), median of %d interleaved runs; world and server step\n"
      "10 at a time; 1-thread columns in thread CPU time, 2-thread columns in wall time\n",
      g_runs);
  std::printf("%6s %5s | %8s %8s %8s %8s | %8s %8s %8s | %7s %7s\n", "robots", "integ", "raw_1t",
              "1model", "world_1t", "serv_1t", "raw_2t", "world_2t", "serv_2t", "ovh_1t%",
              "ovh_2t%");
  for (Integrator integrator : {Integrator::kRk4, Integrator::kEuler}) {
    for (int robots : {1, 16, 64, 128}) {
      const auto r = Measure(robots, integrator);
      std::printf("%6d %5s | %8.2f %8.2f %8.2f %8.2f | %8.2f %8.2f %8.2f | %7.1f %7.1f\n", r.robots,
                  r.integrator, r.us[kRaw1], r.us[kOneModel], r.us[kWorld1], r.us[kServer1],
                  r.us[kRaw2], r.us[kWorld2], r.us[kServer2],
                  100 * (r.us[kServer1] / r.us[kRaw1] - 1),
                  100 * (r.us[kServer2] / r.us[kRaw2] - 1));
      std::fflush(stdout);
    }
  }
  std::printf("own work per robot-step (motor lag + wrench), thread CPU: %.0f ns\n",
              OwnWorkNsPerRobotStep());
  CullingTable();
  return 0;
}

// Cost of recomputing moving pairs' losses, per path-loss model (not a test).
// The layout of physics_bench's obstacle-culling table: 64 robots among 16
// copies of the case study's arrow (scenarios/arrow_flocking.textproto, 10
// boxes each, 50 m apart along y), two pairs per arrow flying east at 5 m/s
// at 10 m beside it, z = 10 m, each drifting sideways at its own speed. Every 10 ms step moves all 64 robots, then
// asks the loss of all 2016 pairs, so every pair is recomputed each step.
// The dead-link loss is the medium's default (16.02 dBm - (-101) dBm), so the
// obstacle walk stops as it does in a run; one row walks every link in full. Prints CPU ns per pair recompute,
// the median of `runs` runs of `seconds` of flight.
// Usage: path_loss_bench [--runs N] [--seconds S] [--only TEXT] (rows whose name holds TEXT,
// e.g. to profile one model)
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mac_phy_sim/channel.h"
#include "mac_phy_sim/three_gpp_v2v.h"
#include "scenario/scenario.h"

namespace sitlnet::mac {
namespace {

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

constexpr int kReplicas = 16;
constexpr double kReplicaPitchM = 50;
constexpr double kPairOffsetM = 16;
constexpr double kStepS = 0.01, kSpeedMps = 5;
// Each robot also drifts sideways at its own speed (robot i: 0.01 (i - 32) m/s), so every
// pair's relative position changes each step and 3GPP's shadowing draws every time.
constexpr double kDriftMpsPerRobot = 0.01;

enum class Kind { kLogDistance, kLogDistanceFullWalk, kTwoRay, kV2vUrban, kV2vHighway };

std::unique_ptr<PathLossModel> MakeModel(Kind kind) {
  MediumConfig config;
  config.path_loss_model = kind == Kind::kTwoRay     ? MediumConfig::PathLoss::kTwoRayGround
                           : kind == Kind::kV2vUrban  ? MediumConfig::PathLoss::kThreeGppV2vUrban
                           : kind == Kind::kV2vHighway ? MediumConfig::PathLoss::kThreeGppV2vHighway
                                                       : MediumConfig::PathLoss::kLogDistance;
  return MakePathLossModel(config, DerivePhyInfo(config));
}

// CPU ns per pair recompute for one run.
double Run(Kind kind, const Scenario& arrow, double seconds) {
  RadioChannel channel(MakeModel(kind), true, 9, 0.4);
  if (kind != Kind::kLogDistanceFullWalk) channel.set_dead_link_loss_db(16.0206 + 101);
  std::vector<Vec3d> where;
  for (int r = 0; r < kReplicas; ++r) {
    const double y0 = kReplicaPitchM * (r - (kReplicas - 1) / 2.0);
    for (const proto::Robot& robot : arrow.spec.robot()) {
      const double y = robot.position_m().y();
      where.push_back(Vec3d{robot.position_m().x(), y0 + y + (y < 0 ? -kPairOffsetM : kPairOffsetM), 10});
      channel.AddStation(where.back());
    }
    for (const proto::Obstacle& box : arrow.spec.obstacle()) {
      channel.AddObstacle(Box{{box.center_m().x(), box.center_m().y() + y0, box.center_m().z()},
                              {box.size_m().x(), box.size_m().y(), box.size_m().z()},
                              box.yaw_deg()});
    }
  }
  const int n = static_cast<int>(where.size());
  const int steps = static_cast<int>(seconds / kStepS);
  double sink = 0;
  const double cpu_start = CpuSeconds();
  for (int s = 0; s < steps; ++s) {
    for (int i = 0; i < n; ++i) {
      where[i].x += kSpeedMps * kStepS;
      where[i].y += kDriftMpsPerRobot * (i - n / 2) * kStepS;
      channel.SetPosition(i, where[i]);
    }
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) sink += channel.LossDb(a, b);
    }
  }
  const double cpu = CpuSeconds() - cpu_start;
  if (sink == 42) std::puts("");  // Keeps the loop.
  return cpu * 1e9 / (static_cast<double>(steps) * n * (n - 1) / 2);
}

}  // namespace
}  // namespace sitlnet::mac

int main(int argc, char** argv) {
  using namespace sitlnet::mac;
  int runs = 5;
  double seconds = 10;
  const char* only = "";
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
      runs = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--runs N] [--seconds S] [--only TEXT]\n", argv[0]);
      return 2;
    }
  }
  const sitlnet::Scenario arrow = sitlnet::LoadScenarioFile(SITLNET_CASE_STUDY_SCENARIO);
  const struct {
    Kind kind;
    const char* name;
  } rows[] = {{Kind::kLogDistance, "log-distance + obstacle walk (today)"},
              {Kind::kLogDistanceFullWalk, "the same, walking every link (no dead-link stop)"},
              {Kind::kTwoRay, "two-ray ground + obstacle walk"},
              {Kind::kV2vUrban, "3GPP V2V urban (condition, path loss, shadowing)"},
              {Kind::kV2vHighway, "3GPP V2V highway (condition, path loss, shadowing)"}};
  std::printf("| model | CPU ns per pair recompute (median of %d) | runs |\n| --- | --- | --- |\n",
              runs);
  for (const auto& row : rows) {
    if (std::strstr(row.name, only) == nullptr) continue;
    std::vector<double> ns;
    for (int k = 0; k < runs; ++k) ns.push_back(Run(row.kind, arrow, seconds));
    std::vector<double> sorted = ns;
    std::sort(sorted.begin(), sorted.end());
    std::printf("| %s | %.1f | %.1f-%.1f |\n", row.name, sorted[sorted.size() / 2], sorted.front(),
                sorted.back());
    std::fflush(stdout);
  }
  return 0;
}

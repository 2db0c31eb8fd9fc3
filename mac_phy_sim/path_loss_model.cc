#include "mac_phy_sim/path_loss_model.h"

#include <cmath>

#include "mac_phy_sim/three_gpp_v2v.h"

namespace sitlnet::mac {
namespace {

constexpr double kSpeedOfLightMps = 299792458.0;  // ns-3 TwoRayGround's C.

double Distance3dM(const PathLossLink& link) {
  const double dx = link.b_m.x - link.a_m.x, dy = link.b_m.y - link.a_m.y,
               dz = link.b_m.z - link.a_m.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

double LogDistanceModel::LossDb(const PathLossLink& link) {
  return LossAtDistanceDb(Distance3dM(link));
}

TwoRayGroundModel::TwoRayGroundModel(const TwoRayGroundParams& params)
    : params_(params), lambda_m_(kSpeedOfLightMps / params.frequency_hz) {}

double TwoRayGroundModel::CrossoverDistanceM(double tx_height_m, double rx_height_m) const {
  return 4 * M_PI * tx_height_m * rx_height_m / lambda_m_;
}

double TwoRayGroundModel::LossDb(const PathLossLink& link) {
  // ns-3 3.37 TwoRayGroundPropagationLossModel::DoCalcRxPower, as a loss.
  const double distance_m = Distance3dM(link);
  if (distance_m <= params_.min_distance_m) return 0;  // ns-3 returns the transmitted power.
  const double tx_height_m = link.a_m.z + params_.height_above_z_m;
  const double rx_height_m = link.b_m.z + params_.height_above_z_m;
  if (distance_m <= CrossoverDistanceM(tx_height_m, rx_height_m)) {
    // Friis: lambda^2 / (16 pi^2 d^2 L).
    const double pi_d = M_PI * distance_m;
    return -10 * std::log10(lambda_m_ * lambda_m_ / (16 * pi_d * pi_d * params_.system_loss));
  }
  const double heights = tx_height_m * rx_height_m, d2 = distance_m * distance_m;
  return -10 * std::log10(heights * heights / (d2 * d2 * params_.system_loss));
}

std::unique_ptr<PathLossModel> MakePathLossModel(const MediumConfig& config, const PhyInfo& phy) {
  switch (config.path_loss_model) {
    case MediumConfig::PathLoss::kLogDistance:
      return std::make_unique<LogDistanceModel>(phy.reference_loss_db, config.path_loss_exponent);
    case MediumConfig::PathLoss::kTwoRayGround:
      return std::make_unique<TwoRayGroundModel>(
          TwoRayGroundParams{phy.path_loss_frequency_hz, config.two_ray_height_above_z_m,
                             config.two_ray_system_loss, config.two_ray_min_distance_m});
    case MediumConfig::PathLoss::kThreeGppV2vUrban:
    case MediumConfig::PathLoss::kThreeGppV2vHighway: {
      ThreeGppV2vParams params;
      params.environment = config.path_loss_model == MediumConfig::PathLoss::kThreeGppV2vUrban
                               ? V2vEnvironment::kUrban
                               : V2vEnvironment::kHighway;
      params.frequency_hz = phy.path_loss_frequency_hz;
      params.shadowing = config.v2v_shadowing;
      params.truck_percent = config.v2v_truck_percent;
      params.update_period_ns = config.v2v_update_period_ns;
      // Streams of their own (tag "3gppv2v"): the MAC's and fading's draws stay as they were.
      params.seed = config.seed ^ 0x3367707076327600ull;
      return std::make_unique<ThreeGppV2vModel>(params);
    }
  }
  SITLNET_DEMAND(false);
  return nullptr;
}

}  // namespace sitlnet::mac

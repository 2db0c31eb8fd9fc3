#include "mac_phy_sim/scenario_adapter.h"

#include "scenario/radio_standard.h"

namespace sitlnet::mac {
namespace {

Vec3d ToVec3(const proto::Vec3& v) { return Vec3d{v.x(), v.y(), v.z()}; }

MediumConfig::PathLoss PathLossFromScenario(proto::Radio::PathLossModel model) {
  switch (model) {
    case proto::Radio::PATH_LOSS_LOG_DISTANCE:
      return MediumConfig::PathLoss::kLogDistance;
    case proto::Radio::PATH_LOSS_TWO_RAY_GROUND:
      return MediumConfig::PathLoss::kTwoRayGround;
    case proto::Radio::PATH_LOSS_THREE_GPP_V2V_URBAN:
      return MediumConfig::PathLoss::kThreeGppV2vUrban;
    case proto::Radio::PATH_LOSS_THREE_GPP_V2V_HIGHWAY:
      return MediumConfig::PathLoss::kThreeGppV2vHighway;
  }
  SITLNET_DEMAND(false);  // The parser refuses unknown enum values.
  return MediumConfig::PathLoss::kLogDistance;
}

}  // namespace

MediumConfig MediumConfigFromScenario(const sitlnet::Scenario& scenario) {
  const proto::Radio& radio = scenario.spec.radio();
  MediumConfig config;
  config.standard = MacStandard(radio.standard());
  config.rate_mbps = radio.rate_mbps();
  config.tx_power_dbm = radio.tx_power_dbm();
  config.noise_figure_db = radio.noise_figure_db();
  config.rx_sensitivity_dbm = radio.rx_sensitivity_dbm();
  config.cca_energy_detect_dbm = radio.cca_energy_detect_dbm();
  config.path_loss_exponent = radio.path_loss_exponent();
  if (radio.has_reference_loss_db()) config.reference_loss_db = radio.reference_loss_db();
  config.shadowing = radio.shadowing();
  config.shadowing_db_per_wall = radio.shadowing_db_per_wall();
  config.shadowing_db_per_m = radio.shadowing_db_per_m();
  config.rts_threshold_bytes = radio.rts_threshold_bytes();
  config.queue_limit_frames = radio.queue_limit_frames();
  config.queue_max_delay_ns = static_cast<TimeNs>(radio.queue_max_delay_ms()) * kNsPerMs;
  if (radio.has_group_rate_mbps()) config.group_rate_mbps = radio.group_rate_mbps();
  config.short_slot = radio.short_slot();
  config.short_preamble = radio.short_preamble();
  if (radio.has_capture_margin_db()) config.capture_margin_db = radio.capture_margin_db();
  config.propagation_delay = radio.propagation_delay();
  config.nakagami_fading = radio.nakagami_fading();
  config.nakagami_m0 = radio.nakagami_m0();
  config.nakagami_m1 = radio.nakagami_m1();
  config.nakagami_m2 = radio.nakagami_m2();
  config.nakagami_d1_m = radio.nakagami_d1_m();
  config.nakagami_d2_m = radio.nakagami_d2_m();
  config.lognormal_shadowing_sigma_db = radio.lognormal_shadowing_sigma_db();
  config.jakes_fading = radio.jakes_fading();
  config.jakes_doppler_hz = radio.jakes_doppler_hz();
  config.jakes_oscillators = static_cast<int>(radio.jakes_oscillators());
  config.jakes_doppler_from_speed = radio.jakes_doppler_from_speed();
  if (radio.rate_control() == proto::Radio::RATE_CONTROL_IDEAL) {
    config.rate_control = MediumConfig::RateControl::kIdeal;
  }
  if (radio.rate_control() == proto::Radio::RATE_CONTROL_MINSTREL) {
    config.rate_control = MediumConfig::RateControl::kMinstrel;
  }
  config.minstrel.update_stats_ns = static_cast<TimeNs>(radio.minstrel_update_stats_ms()) * kNsPerMs;
  config.minstrel.ht_update_stats_ns =
      static_cast<TimeNs>(radio.minstrel_ht_update_stats_ms()) * kNsPerMs;
  config.minstrel.look_around_percent = static_cast<int>(radio.minstrel_look_around_percent());
  config.minstrel.ewma_percent = static_cast<int>(radio.minstrel_ewma_percent());
  config.minstrel.sample_columns = static_cast<int>(radio.minstrel_sample_columns());
  config.minstrel.packet_bytes = static_cast<int>(radio.minstrel_packet_bytes());
  if (radio.error_model() == proto::Radio::ERROR_MODEL_TABLE_BASED) {
    config.error_model = MediumConfig::ErrorModel::kTableBased;
  }
  config.mcs = static_cast<int>(radio.mcs());
  if (radio.has_spatial_streams()) config.spatial_streams = static_cast<int>(radio.spatial_streams());
  if (radio.has_channel_width_mhz()) {
    config.channel_width_mhz = static_cast<int>(radio.channel_width_mhz());
  }
  config.short_guard_interval = radio.short_guard_interval();
  config.qos = radio.qos();
  config.aggregation = radio.aggregation();
  config.max_ampdu_bytes = {radio.ampdu_max_bytes_bk(), radio.ampdu_max_bytes_be(),
                            radio.ampdu_max_bytes_vi(), radio.ampdu_max_bytes_vo()};
  config.path_loss_model = PathLossFromScenario(radio.path_loss_model());
  if (radio.has_path_loss_frequency_mhz()) {
    config.path_loss_frequency_hz = radio.path_loss_frequency_mhz() * 1e6;
  }
  config.two_ray_height_above_z_m = radio.two_ray_height_above_z_m();
  config.two_ray_system_loss = radio.two_ray_system_loss();
  config.two_ray_min_distance_m = radio.two_ray_min_distance_m();
  config.v2v_shadowing = radio.v2v_shadowing();
  config.v2v_truck_percent = radio.v2v_truck_percent();
  config.v2v_update_period_ns = radio.v2v_update_period_ms() * kNsPerMs;
  config.seed = scenario.spec.timing().seed();
  return config;
}

Medium MakeMediumFromScenario(const sitlnet::Scenario& scenario) {
  Medium medium(MediumConfigFromScenario(scenario));
  for (const RobotPlan& robot : scenario.robots) {
    StationRadio radio;
    if (robot.spec.has_tx_power_dbm()) radio.tx_power_dbm = robot.spec.tx_power_dbm();
    if (robot.spec.has_rate_mbps()) radio.rate_mbps = robot.spec.rate_mbps();
    if (robot.spec.has_mcs()) radio.mcs = static_cast<int>(robot.spec.mcs());
    medium.AddStation(robot.wlan_mac, ToVec3(robot.spec.position_m()), radio);
  }
  for (const proto::Obstacle& obstacle : scenario.spec.obstacle()) {
    medium.AddObstacle(
        Box{ToVec3(obstacle.center_m()), ToVec3(obstacle.size_m()), obstacle.yaw_deg()});
  }
  return medium;
}

}  // namespace sitlnet::mac

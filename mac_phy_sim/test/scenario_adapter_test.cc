#include "mac_phy_sim/scenario_adapter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mac_phy_sim/test/saturation_harness.h"
#include "sitlnet/field_options.pb.h"

namespace sitlnet::mac {
namespace {

// MediumConfig's defaults let the library run without a scenario (its tests, tools); a scenario
// that leaves every radio field out must give the very same config, so the proto's defaults and
// the library's cannot drift apart.
TEST(ScenarioAdapterTest, ScenarioDefaultsAreTheLibrarysDefaults) {
  const Scenario scenario = LoadScenarioText("name: \"d\"\nrobot { name: \"a\" }\n", "d.textproto");
  EXPECT_TRUE(MediumConfigFromScenario(scenario) == MediumConfig{});
}

// The medium only asserts what the scenario's options bound (DerivePhyInfo): every radio value at
// either end of its declared range, once loaded, must build a medium without tripping one.
TEST(ScenarioAdapterTest, EveryRadioValueTheScenarioAcceptsBuildsAMedium) {
  const google::protobuf::Descriptor* radio = proto::Radio::descriptor();
  int built = 0;
  for (int i = 0; i < radio->field_count(); ++i) {
    const google::protobuf::FieldDescriptor* field = radio->field(i);
    const auto& options = field->options();
    for (const bool upper : {false, true}) {
      const auto bound = upper ? proto::range_max : proto::range_min;
      if (!options.HasExtension(bound)) continue;
      double value = options.GetExtension(bound);
      if (!upper && options.GetExtension(proto::range_min_open)) value += 1;
      // A path-loss model's parameter is accepted under that model only: try each model.
      int built_for_field = 0;
      const auto* models = proto::Radio::PathLossModel_descriptor();
      for (int m = 0; m < models->value_count(); ++m) {
        Scenario scenario =
            LoadScenarioText("name: \"b\"\nrobot { name: \"a\" }\n", "b.textproto");
        proto::Radio* spec = scenario.spec.mutable_radio();
        spec->set_path_loss_model(
            static_cast<proto::Radio::PathLossModel>(models->value(m)->number()));
        // The MCS fields belong to 802.11n/ac: HT takes MCS 0-15, VHT two streams at MCS 7.
        if (field->name() == "mcs") spec->set_standard(proto::Radio::STANDARD_80211N_5GHZ);
        if (field->name() == "spatial_streams") spec->set_standard(proto::Radio::STANDARD_80211AC);
        // Minstrel's parameters belong to its rate control.
        if (field->name().rfind("minstrel_", 0) == 0) {
          spec->set_rate_control(proto::Radio::RATE_CONTROL_MINSTREL);
        }
        // Minstrel-HT's interval belongs to 802.11n/ac.
        if (field->name() == "minstrel_ht_update_stats_ms") {
          spec->set_standard(proto::Radio::STANDARD_80211N_5GHZ);
        }
        // The A-MPDU sizes too; VHT takes the largest (1048575 B).
        if (field->name().rfind("ampdu_max_bytes_", 0) == 0) {
          spec->set_standard(proto::Radio::STANDARD_80211AC);
        }
        const auto* reflection = spec->GetReflection();
        if (field->cpp_type() == google::protobuf::FieldDescriptor::CPPTYPE_DOUBLE) {
          reflection->SetDouble(spec, field, value);
        } else if (field->cpp_type() == google::protobuf::FieldDescriptor::CPPTYPE_INT64) {
          reflection->SetInt64(spec, field, static_cast<int64_t>(value));
        } else {
          reflection->SetUInt32(spec, field, static_cast<uint32_t>(value));
        }
        try {
          scenario = ValidateScenarioSpec(scenario.spec, "b.textproto");
        } catch (const Error& error) {
          if (std::string(error.what()).find("applies to path_loss_model") != std::string::npos) {
            continue;
          }
          throw;
        }
        Medium medium = MakeMediumFromScenario(scenario);
        EXPECT_EQ(medium.station_count(), 1) << field->name() << " " << value;
        ++built_for_field;
      }
      EXPECT_GE(built_for_field, 1) << field->name() << " " << value;
      built += built_for_field;
    }
  }
  EXPECT_GT(built, 15);
}

TEST(ScenarioAdapterTest, BuildsStationsObstaclesAndRadio) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "adapt"
    robot { name: "a" position_m { x: 0 y: 0 z: 2 } }
    robot { name: "b" position_m { x: 30 y: 0 z: 2 } }
    obstacle { name: "w" center_m { x: 15 y: 0 z: 5 } size_m { x: 2 y: 20 z: 10 } }
    radio { standard: STANDARD_80211G rate_mbps: 24 rts_threshold_bytes: 400 }
    timing { seed: 9 }
  )",
                                             "adapt.textproto");
  const MediumConfig config = MediumConfigFromScenario(scenario);
  EXPECT_EQ(config.standard, Standard::k80211g);
  EXPECT_EQ(config.rate_mbps, 24);
  EXPECT_EQ(config.rts_threshold_bytes, 400u);
  EXPECT_EQ(config.seed, 9u);
  EXPECT_FALSE(config.reference_loss_db.has_value());
  // ns-3 3.37's WifiMacQueue defaults; group frames at the lowest basic rate.
  EXPECT_EQ(config.queue_limit_frames, 500u);
  EXPECT_EQ(config.queue_max_delay_ns, 500 * kNsPerMs);
  EXPECT_FALSE(config.group_rate_mbps.has_value());
  EXPECT_FALSE(config.capture_margin_db.has_value());
  EXPECT_EQ(config.error_model, MediumConfig::ErrorModel::kNist);  // The default.
  Medium medium = MakeMediumFromScenario(scenario);
  ASSERT_EQ(medium.station_count(), 2);
  // Friis at 2.4 GHz + 30 log10(30) + one 2 m box: 2 walls + 0.8 dB.
  EXPECT_NEAR(medium.LossDb(0, 1), 40.046 + 30 * std::log10(30.0) + 18.8, 1e-3);
}

TEST(ScenarioAdapterTest, MapsTheNs3FidelityOptions) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "opts"
    robot { name: "a" tx_power_dbm: 10 }
    robot { name: "b" position_m { x: 5 } rate_mbps: 6 }
    radio {
      standard: STANDARD_80211G rate_mbps: 54 group_rate_mbps: 11 short_slot: true
      short_preamble: true capture_margin_db: 5 queue_limit_frames: 50 queue_max_delay_ms: 0
      propagation_delay: true nakagami_fading: true nakagami_m0: 1 nakagami_d2_m: 150
      lognormal_shadowing_sigma_db: 4 rate_control: RATE_CONTROL_IDEAL
      error_model: ERROR_MODEL_TABLE_BASED
    }
  )",
                                             "opts.textproto");
  const MediumConfig config = MediumConfigFromScenario(scenario);
  EXPECT_EQ(config.group_rate_mbps, 11);
  EXPECT_TRUE(config.short_slot);
  EXPECT_TRUE(config.short_preamble);
  EXPECT_EQ(config.capture_margin_db, 5);
  EXPECT_EQ(config.queue_limit_frames, 50u);
  EXPECT_EQ(config.queue_max_delay_ns, 0);
  EXPECT_EQ(Medium(config).phy().slot_ns, 9 * kNsPerUs);
  EXPECT_TRUE(config.propagation_delay);
  EXPECT_TRUE(config.nakagami_fading);
  EXPECT_EQ(config.nakagami_m0, 1);
  EXPECT_EQ(config.nakagami_m1, 0.75);  // ns-3's default.
  EXPECT_EQ(config.nakagami_d2_m, 150);
  EXPECT_EQ(config.lognormal_shadowing_sigma_db, 4);
  EXPECT_EQ(config.rate_control, MediumConfig::RateControl::kIdeal);
  EXPECT_EQ(config.error_model, MediumConfig::ErrorModel::kTableBased);
}

TEST(ScenarioAdapterTest, MapsMinstrelAndItsParametersWithNs3sDefaults) {
  const MediumConfig defaults = MediumConfigFromScenario(LoadScenarioText(R"(
    name: "m" robot { name: "a" } radio { rate_control: RATE_CONTROL_MINSTREL }
  )", "m.textproto"));
  EXPECT_EQ(defaults.rate_control, MediumConfig::RateControl::kMinstrel);
  // ns-3 3.37 MinstrelWifiManager's attribute defaults.
  EXPECT_EQ(defaults.minstrel, MediumConfig::Minstrel{});
  EXPECT_EQ(defaults.minstrel.update_stats_ns, 100 * kNsPerMs);
  EXPECT_EQ(defaults.minstrel.look_around_percent, 10);
  EXPECT_EQ(defaults.minstrel.ewma_percent, 75);
  EXPECT_EQ(defaults.minstrel.sample_columns, 10);
  EXPECT_EQ(defaults.minstrel.packet_bytes, 1200);
  const MediumConfig set = MediumConfigFromScenario(LoadScenarioText(R"(
    name: "m" robot { name: "a" }
    radio {
      rate_control: RATE_CONTROL_MINSTREL minstrel_update_stats_ms: 50
      minstrel_look_around_percent: 20 minstrel_ewma_percent: 50 minstrel_sample_columns: 4
      minstrel_packet_bytes: 1500
    }
  )", "m.textproto"));
  EXPECT_EQ(set.minstrel.update_stats_ns, 50 * kNsPerMs);
  EXPECT_EQ(set.minstrel.look_around_percent, 20);
  EXPECT_EQ(set.minstrel.ewma_percent, 50);
  EXPECT_EQ(set.minstrel.sample_columns, 4);
  EXPECT_EQ(set.minstrel.packet_bytes, 1500);
  // 802.11n/ac: Minstrel-HT, with MinstrelHtWifiManager's UpdateStatistics default (50 ms).
  const MediumConfig ht = MediumConfigFromScenario(LoadScenarioText(R"(
    name: "m" robot { name: "a" }
    radio { standard: STANDARD_80211AC rate_control: RATE_CONTROL_MINSTREL }
  )", "m.textproto"));
  EXPECT_EQ(ht.rate_control, MediumConfig::RateControl::kMinstrel);
  EXPECT_EQ(ht.minstrel.ht_update_stats_ns, 50 * kNsPerMs);
  const MediumConfig ht_set = MediumConfigFromScenario(LoadScenarioText(R"(
    name: "m" robot { name: "a" }
    radio {
      standard: STANDARD_80211N_2_4GHZ rate_control: RATE_CONTROL_MINSTREL
      minstrel_ht_update_stats_ms: 80
    }
  )", "m.textproto"));
  EXPECT_EQ(ht_set.minstrel.ht_update_stats_ns, 80 * kNsPerMs);
}

TEST(ScenarioAdapterTest, MapsJakesFading) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "jakes"
    robot { name: "a" }
    radio { jakes_fading: true jakes_doppler_hz: 12.5 jakes_oscillators: 8
            jakes_doppler_from_speed: true }
  )",
                                             "jakes.textproto");
  const MediumConfig config = MediumConfigFromScenario(scenario);
  EXPECT_TRUE(config.jakes_fading);
  EXPECT_EQ(config.jakes_doppler_hz, 12.5);
  EXPECT_EQ(config.jakes_oscillators, 8);
  EXPECT_TRUE(config.jakes_doppler_from_speed);
  EXPECT_EQ(MediumConfig{}.jakes_doppler_hz, 80);  // ns-3's DopplerFrequencyHz.
  EXPECT_EQ(MediumConfig{}.jakes_oscillators, 20);  // ns-3's NumberOfOscillators.
}

// Bad Jakes settings are refused in one line naming the file, line, column and field.
TEST(ScenarioAdapterTest, RefusesBadJakesSettings) {
  const std::pair<const char*, const char*> cases[] = {
      {"radio { jakes_doppler_hz: 0 }", "t.textproto:3:9: radio: jakes_doppler_hz 0 must be > 0"},
      {"radio { jakes_doppler_hz: 20000 }",
       "t.textproto:3:9: radio: jakes_doppler_hz 20000 must be at most 10000"},
      {"radio { jakes_oscillators: 3 }",
       "t.textproto:3:9: radio: jakes_oscillators 3 out of range [4, 1000]"},
      {"radio { nakagami_fading: true jakes_fading: true }",
       "t.textproto:3:31: radio: jakes_fading and nakagami_fading both model fast fading; set one"},
      {"radio { jakes_doppler_from_speed: true }",
       "t.textproto:3:9: radio: jakes_doppler_from_speed needs jakes_fading"},
  };
  for (const auto& [radio, message] : cases) {
    const std::string text = std::string("name: \"t\"\nrobot { name: \"a\" }\n") + radio + "\n";
    try {
      LoadScenarioText(text, "t.textproto");
      ADD_FAILURE() << "accepted: " << radio;
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()), message);
    }
  }
}

TEST(ScenarioAdapterTest, MapsThePathLossModels) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "pl"
    robot { name: "a" position_m { z: 2 } }
    robot { name: "b" position_m { x: 10 z: 2 } }
    radio {
      path_loss_model: PATH_LOSS_TWO_RAY_GROUND path_loss_frequency_mhz: 5900
      two_ray_height_above_z_m: 1 two_ray_system_loss: 2 two_ray_min_distance_m: 3
    }
  )",
                                             "pl.textproto");
  const MediumConfig config = MediumConfigFromScenario(scenario);
  EXPECT_EQ(config.path_loss_model, MediumConfig::PathLoss::kTwoRayGround);
  EXPECT_EQ(config.path_loss_frequency_hz, 5.9e9);
  EXPECT_EQ(config.two_ray_height_above_z_m, 1);
  EXPECT_EQ(config.two_ray_system_loss, 2);
  EXPECT_EQ(config.two_ray_min_distance_m, 3);
  // Friis at 5.9 GHz over 10 m (crossover 4 pi 3 3 / lambda = 2226 m) plus 3.0103 dB.
  const double lambda_m = 299792458.0 / 5.9e9;
  EXPECT_NEAR(MakeMediumFromScenario(scenario).LossDb(0, 1),
              20 * std::log10(4 * M_PI * 10 / lambda_m) + 10 * std::log10(2.0), 1e-9);
  for (const char* model : {"PATH_LOSS_THREE_GPP_V2V_URBAN", "PATH_LOSS_THREE_GPP_V2V_HIGHWAY"}) {
    const Scenario v2v = LoadScenarioText(
        std::string("name: \"v\"\nrobot { name: \"a\" }\nradio { path_loss_model: ") + model +
            " v2v_shadowing: false v2v_truck_percent: 20 v2v_update_period_ms: 250 }\n",
        "v.textproto");
    const MediumConfig v2v_config = MediumConfigFromScenario(v2v);
    EXPECT_NE(v2v_config.path_loss_model, MediumConfig::PathLoss::kLogDistance);
    EXPECT_FALSE(v2v_config.v2v_shadowing);
    EXPECT_EQ(v2v_config.v2v_truck_percent, 20);
    EXPECT_EQ(v2v_config.v2v_update_period_ns, 250 * kNsPerMs);
  }
}

// Bad values are refused with one line naming the file, line, column and field.
TEST(ScenarioAdapterTest, RefusesBadPathLossFieldsInOneLocatedLine) {
  auto message = [](const std::string& radio) {
    try {
      LoadScenarioText("name: \"t\"\nrobot { name: \"a\" }\nradio { " + radio + " }\n",
                       "t.textproto");
    } catch (const Error& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("path_loss_frequency_mhz: 200"),
            "t.textproto:3:9: radio: path_loss_frequency_mhz 200 out of range [500, 100000]");
  EXPECT_EQ(message("two_ray_system_loss: 0.5"),
            "t.textproto:3:9: radio: two_ray_system_loss 0.5 out of range [1, 1000]");
  EXPECT_EQ(message("v2v_truck_percent: 101"),
            "t.textproto:3:9: radio: v2v_truck_percent 101 out of range [0, 100]");
  EXPECT_EQ(message("v2v_update_period_ms: -1"),
            "t.textproto:3:9: radio: v2v_update_period_ms -1 out of range [0, 86400000]");
  EXPECT_NE(message("path_loss_model: PATH_LOSS_FOO").find("t.textproto:3:"), std::string::npos);
}

// radio.qos makes a/b/g stations QoS stations; n/ac always are, and `qos: false` there is refused.
TEST(ScenarioAdapterTest, MapsQosAndRefusesItOffForHtInOneLocatedLine) {
  const std::string head = "name: \"t\"\nrobot { name: \"a\" }\nradio { ";
  EXPECT_TRUE(MediumConfigFromScenario(LoadScenarioText(head + "qos: true }\n", "t.textproto")).qos);
  EXPECT_FALSE(MediumConfigFromScenario(LoadScenarioText(head + "}\n", "t.textproto")).qos);
  const Scenario ht = LoadScenarioText(head + "standard: STANDARD_80211N_5GHZ }\n", "t.textproto");
  EXPECT_TRUE(DerivePhyInfo(MediumConfigFromScenario(ht)).qos);
  try {
    LoadScenarioText(head + "standard: STANDARD_80211AC qos: false }\n", "t.textproto");
    ADD_FAILURE() << "accepted";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "t.textproto:3:36: radio: qos false: 802.11n/ac stations are always QoS stations "
              "(as in ns-3 3.37)");
  }
}

// Robot a sends 100 B to b at 0, b to a at 5 ms: the deliveries by 10 ms.
std::vector<Delivery> ExchangeOneFrameEachWay(Medium& medium) {
  medium.SubmitFrame(0, testing::MakeEthernetFrame(RobotMac(1), RobotMac(0), 100), 0);
  medium.SubmitFrame(1, testing::MakeEthernetFrame(RobotMac(0), RobotMac(1), 100), 5 * kNsPerMs);
  std::vector<Delivery> out;
  medium.AdvanceTo(10 * kNsPerMs, &out);
  return out;
}

TEST(ScenarioAdapterTest, RobotsHaveTheirOwnTxPowerAndRate) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "own"
    robot { name: "a" tx_power_dbm: 10 }
    robot { name: "b" position_m { x: 5 } rate_mbps: 6 }
  )",
                                             "own.textproto");
  Medium medium = MakeMediumFromScenario(scenario);
  medium.EnableTrace(true);
  const std::vector<Delivery> out = ExchangeOneFrameEachWay(medium);
  ASSERT_EQ(out.size(), 2u);
  // a at 10 dBm: b receives 10 - (46.6777 + 30 log10 5) dBm; b at the default 16.0206 dBm.
  EXPECT_NEAR(out[0].rx_power_dbm, 10 - 46.6777 - 30 * std::log10(5.0), 1e-3);
  EXPECT_NEAR(out[1].rx_power_dbm, 16.0206 - 46.6777 - 30 * std::log10(5.0), 1e-3);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  ASSERT_EQ(trace.size(), 4u);
  EXPECT_EQ(trace[0].tx->rate_mbps, 54);  // a: the scenario's rate.
  EXPECT_EQ(trace[2].tx->rate_mbps, 6);   // b: its own.
}

TEST(ScenarioAdapterTest, HtRadioAndRobotsOwnMcs) {
  const Scenario scenario = LoadScenarioText(R"(
    name: "ht"
    radio { standard: STANDARD_80211N_5GHZ mcs: 4 channel_width_mhz: 40 short_guard_interval: true }
    robot { name: "a" }
    robot { name: "b" position_m { x: 5 } mcs: 15 }
  )",
                                             "ht.textproto");
  Medium medium = MakeMediumFromScenario(scenario);
  medium.EnableTrace(true);
  const std::vector<Delivery> out = ExchangeOneFrameEachWay(medium);
  ASSERT_EQ(out.size(), 2u);
  const std::vector<TxRecord> txs = testing::DrainTransmissions(medium);
  ASSERT_EQ(txs.size(), 4u);
  // 108 data subcarriers x 4 bits x 3/4 per 3.6 us symbol: 90 Mb/s; b: 64-QAM 5/6, two streams.
  EXPECT_EQ(txs[0].mcs, 4);
  EXPECT_NEAR(txs[0].rate_mbps, 90, 1e-9);
  EXPECT_EQ(txs[2].mcs, 15);
  EXPECT_EQ(txs[2].spatial_streams, 2);
  EXPECT_NEAR(txs[2].rate_mbps, 300, 1e-9);
  EXPECT_TRUE(txs[2].short_guard_interval);
  EXPECT_EQ(txs[2].channel_width_mhz, 40);
}

}  // namespace
}  // namespace sitlnet::mac

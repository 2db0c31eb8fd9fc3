#include "scenario/scenario.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sitlnet {
namespace {

std::string SourceDir() {
  const char* dir = std::getenv("SITLNET_SOURCE_DIR");
  return dir ? dir : ".";
}

// Expects loading `text` to fail with a message that starts with `location`
// and contains `rule`.
void ExpectRejected(const std::string& text, const std::string& location, const std::string& rule) {
  try {
    LoadScenarioText(text, "t.textproto");
    FAIL() << "accepted: " << text;
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(location, 0), 0u) << message;
    EXPECT_NE(message.find(rule), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
  }
}

constexpr char kTwo[] = "name: \"t\"\nrobot { name: \"a\" }\nrobot { name: \"b\" }\n";

TEST(ScenarioTest, ShippedExamplesLoad) {
  for (const char* file :
       {"two_robots", "line3", "arrow_flocking", "px4_fleet", "ardupilot_fleet", "qos_video"}) {
    const Scenario scenario = LoadScenarioFile(SourceDir() + "/scenarios/" + file + ".textproto");
    EXPECT_FALSE(scenario.robots.empty()) << file;
  }
}

TEST(ScenarioTest, DerivesNamesAddressesAndDefaults) {
  const Scenario scenario = LoadScenarioText(kTwo, "t.textproto");
  ASSERT_EQ(scenario.robots.size(), 2u);
  const RobotPlan& b = scenario.robots[1];
  EXPECT_EQ(b.netns, "t-b");
  EXPECT_EQ(b.root_veth, "t-c1");
  EXPECT_EQ(FormatMac(b.wlan_mac), "02:00:00:00:00:01");
  EXPECT_EQ(FormatIpv4(b.wlan_address), "10.77.0.2");
  EXPECT_EQ(FormatIpv4(b.ctl_root_address), "10.78.0.5");
  EXPECT_EQ(FormatIpv4(b.ctl_robot_address), "10.78.0.6");
  EXPECT_EQ(scenario.iteration_ns, 10'000'000);
  EXPECT_EQ(scenario.physics_steps_per_iteration, 10);
  EXPECT_EQ(scenario.network_steps_per_iteration, 1);
  EXPECT_DOUBLE_EQ(scenario.spec.radio().tx_power_dbm(), 16.0206);
  EXPECT_DOUBLE_EQ(b.airframe.mass_kg(), 1.325);
  EXPECT_EQ(scenario.RobotIndex("b"), 1);
  EXPECT_EQ(scenario.RobotIndex("zz"), -1);
}

// The command line's overrides edit the spec in memory and validate it again, never through text.
TEST(ScenarioTest, EditedSpecValidatesWithoutText) {
  proto::Scenario spec = LoadScenarioText(kTwo, "t.textproto").spec;
  spec.mutable_timing()->set_pacing(ProtoPacing(clock::Pacing::kLockstep));
  EXPECT_EQ(ValidateScenarioSpec(spec, "t.textproto").pacing(), clock::Pacing::kLockstep);
  spec.mutable_radio()->set_tx_power_dbm(40);
  try {
    ValidateScenarioSpec(spec, "t.textproto (with overrides)");
    FAIL();
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "t.textproto (with overrides): radio: tx_power_dbm 40 out of range [-10, 30]");
  }
}

TEST(ScenarioTest, SyntaxErrorNamesLineAndColumn) {
  ExpectRejected("name: \"t\"\nrobot { nme: \"a\" }\n", "t.textproto:2:", "no field named \"nme\"");
}

TEST(ScenarioTest, RejectsBadScenarioNames) {
  ExpectRejected("name: \"Bad-Name\"\nrobot { name: \"a\" }\n", "t.textproto:1:1", "scenario name");
  ExpectRejected("name: \"elevenchars\"\nrobot { name: \"a\" }\n", "t.textproto:1:1", "1..10");
}

TEST(ScenarioTest, RejectsDuplicateAndOverlongRobotNames) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" }\nrobot { name: \"a\" }\n", "t.textproto:3:9",
                 "robot \"a\": duplicate robot name");
  ExpectRejected("name: \"t\"\nrobot { name: \"" + std::string(33, 'x') + "\" }\n",
                 "t.textproto:2:9", "1..32");
  ExpectRejected("name: \"t\"\nrobot { name: \"a-b\" }\n", "t.textproto:2:9", "characters");
}

TEST(ScenarioTest, RejectsNoRobots) { ExpectRejected("name: \"t\"\n", "t.textproto", "robot"); }

TEST(ScenarioTest, RejectsIterationNotMultipleOfStep) {
  ExpectRejected(
      std::string(kTwo) + "timing {\n  iteration_us: 10000\n  physics_step_us: 3000\n}\n",
      "t.textproto:6:3", "not a whole multiple of physics_step_us 3000");
  ExpectRejected(std::string(kTwo) + "timing { network_step_us: 0 }\n", "t.textproto:4:10",
                 "must be > 0");
}

TEST(ScenarioTest, RejectsOutOfRangeRadio) {
  ExpectRejected(std::string(kTwo) + "radio { tx_power_dbm: 40 }\n", "t.textproto:4:9",
                 "tx_power_dbm 40 out of range [-10, 30]");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211B rate_mbps: 54 }\n",
                 "t.textproto:4:35", "not a rate of STANDARD_80211B");
  ExpectRejected(std::string(kTwo) + "radio { group_rate_mbps: 11 }\n", "t.textproto:4:9",
                 "group_rate_mbps 11 is not a rate of STANDARD_80211A");
  ExpectRejected(std::string(kTwo) + "radio { short_slot: true }\n", "t.textproto:4:9",
                 "short_slot applies to STANDARD_80211G only");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" rate_mbps: 11 }\n", "t.textproto:2:19",
                 "robot \"a\": rate_mbps 11 is not a rate of STANDARD_80211A");
}

TEST(ScenarioTest, RejectsBadHtVhtModes) {
  // Column of the offending field: "radio { " is 8 characters, so the first field is at 9.
  ExpectRejected(std::string(kTwo) + "radio { mcs: 3 }\n", "t.textproto:4:9",
                 "mcs applies to STANDARD_80211N_* and STANDARD_80211AC only");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211N_5GHZ rate_mbps: 54 }\n",
                 "t.textproto:4:40", "rate_mbps applies to 802.11a/b/g");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211AC mcs: 9 channel_width_mhz: 20 }\n",
                 "t.textproto:4:36", "VHT mcs 9 is not valid at 20 MHz with 1 spatial stream(s)");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211N_5GHZ channel_width_mhz: 80 }\n",
                 "t.textproto:4:40", "channel_width_mhz 80 is not a width of 802.11n (20, 40)");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211N_5GHZ mcs: 7 spatial_streams: 2 }\n",
                 "t.textproto:4:47", "spatial_streams 2 does not match HT mcs 7");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211AC mcs: 10 }\n",
                 "t.textproto:4:36", "mcs 10 out of range [0, 9] for 802.11ac");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211N_5GHZ mcs: 16 }\n",
                 "t.textproto:4:40", "mcs 16 out of range [0, 15]");
  // A-MPDU fields: 802.11n/ac only, sizes within ns-3's cap (block_ack.h).
  ExpectRejected(std::string(kTwo) + "radio { aggregation: false }\n", "t.textproto:4:9",
                 "aggregation applies to STANDARD_80211N_* and STANDARD_80211AC only");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211AC ampdu_max_bytes_be: 2000000 }\n",
                 "t.textproto:4:36", "ampdu_max_bytes_be 2000000 out of range [0, 1048575]");
  ExpectRejected("name: \"t\"\nradio { standard: STANDARD_80211AC channel_width_mhz: 20 }\n"
                 "robot { name: \"a\" mcs: 9 }\n",
                 "t.textproto:3:19", "robot \"a\": VHT mcs 9 is not valid at 20 MHz");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" mcs: 1 }\n", "t.textproto:2:19",
                 "robot \"a\": mcs applies to STANDARD_80211N_* and STANDARD_80211AC only");
  // Accepted: HT MCS 15 (two streams from the index) at 40 MHz, short GI; VHT MCS 9 at 80 MHz.
  EXPECT_NO_THROW(LoadScenarioText(
      std::string(kTwo) + "radio { standard: STANDARD_80211N_2_4GHZ mcs: 15 channel_width_mhz: 40 "
                          "short_guard_interval: true }\n",
      "t.textproto"));
  EXPECT_NO_THROW(LoadScenarioText(
      std::string(kTwo) + "radio { standard: STANDARD_80211AC mcs: 9 spatial_streams: 2 }\n",
      "t.textproto"));
}

// Minstrel is Minstrel-HT on n/ac, which has no look-around share or legacy interval; Ideal is
// a/b/g only; Minstrel's parameters would be ignored under another rate control. All refused,
// located.
TEST(ScenarioTest, RejectsMinstrelParametersWhereTheyDoNothing) {
  ExpectRejected(std::string(kTwo) +
                     "radio { standard: STANDARD_80211N_5GHZ rate_control: RATE_CONTROL_IDEAL }\n",
                 "t.textproto:4:40",
                 "radio: rate_control RATE_CONTROL_IDEAL is modelled for 802.11a/b/g only");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211N_5GHZ rate_control: "
                                     "RATE_CONTROL_MINSTREL minstrel_look_around_percent: 20 }\n",
                 "t.textproto:4:76",
                 "radio: minstrel_look_around_percent applies to 802.11a/b/g Minstrel; 802.11n/ac "
                 "run Minstrel-HT (its interval: minstrel_ht_update_stats_ms)");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211G rate_control: "
                                     "RATE_CONTROL_MINSTREL minstrel_ht_update_stats_ms: 20 }\n",
                 "t.textproto:4:71",
                 "radio: minstrel_ht_update_stats_ms applies to STANDARD_80211N_* and "
                 "STANDARD_80211AC only");
  ExpectRejected(std::string(kTwo) + "radio { standard: STANDARD_80211AC "
                                     "minstrel_ht_update_stats_ms: 20 }\n",
                 "t.textproto:4:36",
                 "radio: minstrel_ht_update_stats_ms applies to rate_control "
                 "RATE_CONTROL_MINSTREL only");
  EXPECT_NO_THROW(LoadScenarioText(
      std::string(kTwo) + "radio { standard: STANDARD_80211AC rate_control: RATE_CONTROL_MINSTREL "
                          "minstrel_ht_update_stats_ms: 100 minstrel_ewma_percent: 50 }\n",
      "t.textproto"));
  // A robot's own MCS means nothing under Minstrel-HT.
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" mcs: 3 }\nrobot { name: \"b\" }\n"
                 "radio { standard: STANDARD_80211N_5GHZ rate_control: RATE_CONTROL_MINSTREL }\n",
                 "t.textproto:2:19",
                 "robot \"a\": mcs would be ignored: Minstrel-HT (rate_control "
                 "RATE_CONTROL_MINSTREL) chooses every robot's MCS");
  ExpectRejected(std::string(kTwo) + "radio { minstrel_ewma_percent: 50 }\n", "t.textproto:4:9",
                 "radio: minstrel_ewma_percent applies to rate_control RATE_CONTROL_MINSTREL only");
  ExpectRejected(std::string(kTwo) +
                     "radio { rate_control: RATE_CONTROL_MINSTREL minstrel_look_around_percent: 101 }\n",
                 "t.textproto:4:45", "minstrel_look_around_percent 101 out of range");
  ExpectRejected(std::string(kTwo) +
                     "radio { rate_control: RATE_CONTROL_MINSTREL rts_threshold_bytes: 100 "
                     "queue_max_delay_ms: 0 }\n",
                 "t.textproto:4:70", "radio: queue_max_delay_ms 0 (frames never expire)");
  ExpectRejected(std::string(kTwo) +
                     "radio { standard: STANDARD_80211N_5GHZ aggregation: true "
                     "queue_max_delay_ms: 0 }\n",
                 "t.textproto:4:58",
                 "radio: queue_max_delay_ms 0 (frames never expire) with aggregation");
  EXPECT_NO_THROW(LoadScenarioText(
      std::string(kTwo) + "radio { standard: STANDARD_80211G rate_control: RATE_CONTROL_MINSTREL "
                          "minstrel_update_stats_ms: 50 minstrel_sample_columns: 4 }\n",
      "t.textproto"));
}

// A parameter of a path-loss model that is not chosen would be ignored: refused, located.
TEST(ScenarioTest, RejectsParametersOfAPathLossModelNotChosen) {
  ExpectRejected(std::string(kTwo) + "radio { two_ray_system_loss: 2 }\n", "t.textproto:4:9",
                 "radio: two_ray_system_loss applies to path_loss_model PATH_LOSS_TWO_RAY_GROUND "
                 "only, not PATH_LOSS_LOG_DISTANCE");
  ExpectRejected(std::string(kTwo) +
                     "radio {\n  path_loss_model: PATH_LOSS_THREE_GPP_V2V_URBAN\n"
                     "  two_ray_height_above_z_m: 1\n}\n",
                 "t.textproto:6:3", "two_ray_height_above_z_m applies to path_loss_model");
  ExpectRejected(std::string(kTwo) +
                     "radio { path_loss_model: PATH_LOSS_TWO_RAY_GROUND v2v_truck_percent: 10 }\n",
                 "t.textproto:4:51",
                 "radio: v2v_truck_percent applies to path_loss_model "
                 "PATH_LOSS_THREE_GPP_V2V_URBAN or PATH_LOSS_THREE_GPP_V2V_HIGHWAY only, not "
                 "PATH_LOSS_TWO_RAY_GROUND");
  ExpectRejected(std::string(kTwo) + "radio { v2v_shadowing: false }\n", "t.textproto:4:9",
                 "v2v_shadowing applies to path_loss_model");
  ExpectRejected(std::string(kTwo) + "radio { v2v_update_period_ms: 100 }\n", "t.textproto:4:9",
                 "v2v_update_period_ms applies to path_loss_model");
  ExpectRejected(std::string(kTwo) + "radio { path_loss_frequency_mhz: 5900 }\n",
                 "t.textproto:4:9",
                 "path_loss_frequency_mhz applies to path_loss_model PATH_LOSS_TWO_RAY_GROUND, "
                 "PATH_LOSS_THREE_GPP_V2V_URBAN or PATH_LOSS_THREE_GPP_V2V_HIGHWAY only");
  // Each model's own parameters, and the frequency shared by three of them, are accepted.
  for (const char* radio :
       {"path_loss_model: PATH_LOSS_TWO_RAY_GROUND path_loss_frequency_mhz: 5900 "
        "two_ray_height_above_z_m: 1 two_ray_system_loss: 2 two_ray_min_distance_m: 1",
        "path_loss_model: PATH_LOSS_THREE_GPP_V2V_URBAN path_loss_frequency_mhz: 5900 "
        "v2v_shadowing: false v2v_truck_percent: 10",
        "path_loss_model: PATH_LOSS_THREE_GPP_V2V_HIGHWAY v2v_truck_percent: 10 "
        "v2v_update_period_ms: 100"}) {
    EXPECT_NO_THROW(LoadScenarioText(std::string(kTwo) + "radio { " + radio + " }\n",
                                     "t.textproto"))
        << radio;
  }
}

TEST(ScenarioTest, RejectsAddressesOutsideOrClashing) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" wlan_address: \"10.9.0.1\" }\n",
                 "t.textproto:2:19", "not a host address of 10.77.0.0/24");
  ExpectRejected(
      "name: \"t\"\nrobot { name: \"a\" }\nrobot { name: \"b\" wlan_address: \"10.77.0.1\" }\n",
      "t.textproto:3:1", "already used");
  ExpectRejected(std::string(kTwo) + "addresses { wlan_subnet: \"10.78.0.0/24\" }\n",
                 "t.textproto:4:13", "overlaps wlan_subnet");
  ExpectRejected(std::string(kTwo) + "addresses { wlan_subnet: \"10.77.0.1/24\" }\n",
                 "t.textproto:4:13", "no host bits");
  ExpectRejected(std::string(kTwo) +
                     "addresses { wlan_subnet: \"10.77.0.0/30\" }\n"
                     "robot { name: \"c\" }\n",
                 "t.textproto:4:13", "no room for 3 robots");
}

TEST(ScenarioTest, RejectsUnknownAirframeAndBadObstacle) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" airframe: \"x9\" }\n", "t.textproto:2:19",
                 "unknown airframe \"x9\"");
  ExpectRejected(std::string(kTwo) + "obstacle { size_m { x: 1 y: 0 z: 1 } }\n", "t.textproto:4:12",
                 "size_m");
}

// Every numeric field is finite and in range (an audit found NaN/inf, 4e9 lidar rays, negative
// noise and overflowing durations accepted).
TEST(ScenarioTest, RejectsNonFiniteAndOutOfRangeNumbers) {
  const std::string two = kTwo;
  ExpectRejected(two + "obstacle { size_m { x: 1 y: 1 z: 1 } center_m { x: nan } }\n",
                 "t.textproto:4:38", "center_m must be finite");
  ExpectRejected(two + "obstacle { size_m { x: inf y: 1 z: 1 } }\n", "t.textproto:4:12", "size_m");
  ExpectRejected(two + "obstacle { size_m { x: 1 y: 1 z: 1 } yaw_deg: inf }\n", "t.textproto:4:38",
                 "yaw_deg inf out of range");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" yaw_deg: nan }\n", "t.textproto:2:19",
                 "yaw_deg nan out of range");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" lidar { rays: 4000000000 } }\n",
                 "t.textproto:2:27", "lidar rays 4000000000 out of range");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" imu { gyro_noise_rad_s: -1 } }\n",
                 "t.textproto:2:25", "imu gyro_noise_rad_s -1 out of range");
  ExpectRejected(two + "timing { duration_ms: 9223372036854 }\n", "t.textproto:4:10",
                 "duration_ms 9223372036854 must be at most");
  ExpectRejected(two + "timing { realtime_factor: 1e-300 }\n", "t.textproto:4:10",
                 "realtime_factor 1e-300 must be in");
  ExpectRejected(two + "timing { ros2_clock_hz: 5000 }\n", "t.textproto:4:10",
                 "ros2_clock_hz 5000.000000 must be 0 (off) or in (0, 1000");
  ExpectRejected(two + "timing { ros2_clock_hz: nan }\n", "t.textproto:4:10",
                 "ros2_clock_hz nan must be 0 (off)");
  ExpectRejected(two + "radio { noise_figure_db: nan }\n", "t.textproto:4:9",
                 "noise_figure_db nan out of range");
}

TEST(ScenarioTest, HostRouteClashIsRefused) {
  const Scenario scenario = LoadScenarioText(kTwo, "t.textproto");
  const std::vector<HostRoute> fine = {{*ParseIpv4Prefix("0.0.0.0/0"), "eth0"},
                                       {*ParseIpv4Prefix("192.0.2.0/24"), "eth0"}};
  EXPECT_NO_THROW(CheckAddressPlanAgainstRoutes(scenario, fine));
  const std::vector<HostRoute> clash = {{*ParseIpv4Prefix("10.0.0.0/8"), "vpn0"}};
  try {
    CheckAddressPlanAgainstRoutes(scenario, clash);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what())
                  .find("wlan_subnet 10.77.0.0/24 overlaps host route "
                        "10.0.0.0/8 dev vpn0"),
              std::string::npos)
        << error.what();
  }
}

TEST(ScenarioTest, MissingFileNamesThePath) {
  EXPECT_THROW(
      {
        try {
          LoadScenarioFile("/nonexistent/x.textproto");
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("/nonexistent/x.textproto"), std::string::npos);
          throw;
        }
      },
      Error);
}

TEST(ScenarioTest, GeodeticOriginDefaultsAndRanges) {
  const Scenario plain = LoadScenarioText(kTwo, "t.textproto");
  EXPECT_DOUBLE_EQ(plain.spec.geodetic_origin().latitude_deg(), 47.397742);
  EXPECT_DOUBLE_EQ(plain.spec.geodetic_origin().magnetic_field().intensity_gauss(), 0.483637);
  // Line 4 column 36: the offending field inside the block.
  ExpectRejected(std::string(kTwo) +
                     "geodetic_origin { magnetic_field {} latitude_deg: 91 longitude_deg: 0 }\n",
                 "t.textproto:4:37", "latitude_deg 91 out of range");
  ExpectRejected(std::string(kTwo) + "geodetic_origin { altitude_m: 12000 }\n", "t.textproto:4:19",
                 "altitude_m 12000 out of range");
  // Another place without its magnetic field: refused rather than given Zurich's.
  ExpectRejected(std::string(kTwo) + "geodetic_origin { latitude_deg: 10 }\n", "t.textproto:4:1",
                 "needs magnetic_field");
  ExpectRejected(std::string(kTwo) + "geodetic_origin { magnetic_field { intensity_gauss: 5 } }\n",
                 "t.textproto:4:36", "intensity_gauss 5 out of range");
  const Scenario moved = LoadScenarioText(
      std::string(kTwo) +
          "geodetic_origin { latitude_deg: -33.9 longitude_deg: 151.2 altitude_m: 20\n"
          "  magnetic_field { declination_deg: 12.9 inclination_deg: -64.4 "
          "intensity_gauss: 0.575 } }\n",
      "t.textproto");
  EXPECT_DOUBLE_EQ(moved.spec.geodetic_origin().magnetic_field().inclination_deg(), -64.4);
}

TEST(ScenarioTest, RejectsBadHilSensorFigures) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" gps { rate_hz: 0 } }\n",
                 "t.textproto:2:", "gps rate_hz 0 out of range");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" gps { delay_ms: -1 } }\n", "t.textproto:2:",
                 "gps delay_ms -1 out of range [0, 10000]");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" barometer { noise_pa: -1 } }\n",
                 "t.textproto:2:", "barometer noise_pa -1 must be finite and >= 0");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" gps { satellites: 255 } }\n",
                 "t.textproto:2:", "satellites must be <= 254");
}

TEST(ScenarioTest, RejectsBadAutopilotPorts) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" px4_sim_port: 70000 }\n", "t.textproto:2:",
                 "px4_sim_port 70000 out of range [0, 65535]");
  ExpectRejected(
      "name: \"t\"\nrobot { name: \"a\" px4_sim_port: 4560 ardupilot_json_port: 9002 }\n",
      "t.textproto:2:", "has both ardupilot_json_port and px4_sim_port");
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" ground_station: true px4_sim_port: 4560 }\n",
                 "t.textproto:2:", "is a ground station: it has no physics");
}

//--------------------------------- Nodes ------------------------------------

// Robot names r0..r<count-1>, one per line from line 3 (after the name and node lines).
std::string Robots(int count, const std::string& extra = "") {
  std::string text;
  for (int i = 0; i < count; ++i) {
    text += "robot { name: \"r" + std::to_string(i) + "\"" + extra + " }\n";
  }
  return text;
}

std::vector<std::vector<int>> NodeRobots(const Scenario& scenario) {
  std::vector<std::vector<int>> robots;
  for (const NodePlan& node : scenario.nodes) robots.push_back(node.robots);
  return robots;
}

TEST(ScenarioTest, WithoutNodesEveryRobotIsOnNoNode) {
  const Scenario scenario = LoadScenarioText(kTwo, "t.textproto");
  EXPECT_TRUE(scenario.nodes.empty());
  EXPECT_EQ(scenario.robots[0].node, -1);
  EXPECT_EQ(scenario.robots[1].node, -1);
}

TEST(ScenarioTest, ExplicitNodesCollectTheirRobotsAscending) {
  const Scenario scenario = LoadScenarioText(
      "name: \"t\"\nnodes { name: \"n0\" }\nnodes { name: \"node-1\" }\n"
      "robot { name: \"a\" node: \"node-1\" }\nrobot { name: \"b\" node: \"n0\" }\n"
      "robot { name: \"c\" node: \"node-1\" }\n",
      "t.textproto");
  ASSERT_EQ(scenario.nodes.size(), 2u);
  EXPECT_EQ(scenario.nodes[0].name, "n0");
  EXPECT_EQ(scenario.nodes[1].name, "node-1");
  EXPECT_EQ(NodeRobots(scenario), (std::vector<std::vector<int>>{{1}, {0, 2}}));
  EXPECT_EQ(scenario.robots[0].node, 1);
  EXPECT_EQ(scenario.robots[1].node, 0);
  EXPECT_EQ(scenario.robots[2].node, 1);
  EXPECT_EQ(scenario.NodeIndex("node-1"), 1);
  EXPECT_EQ(scenario.NodeIndex("n9"), -1);
}

TEST(ScenarioTest, BlocksPutRobotIOnNodeIAndNodesOverRobots) {
  const std::string blocks = "node_assignment: NODE_ASSIGNMENT_BLOCKS\n";
  // 5 robots on 2 nodes: floor(i * 2 / 5) = 0 0 0 1 1.
  const Scenario five = LoadScenarioText(
      "name: \"t\"\nnodes { name: \"a\" }\nnodes { name: \"b\" }\n" + blocks + Robots(5),
      "t.textproto");
  EXPECT_EQ(NodeRobots(five), (std::vector<std::vector<int>>{{0, 1, 2}, {3, 4}}));
  EXPECT_EQ(five.robots[3].node, 1);
  // 4 robots on 3 nodes: floor(i * 3 / 4) = 0 0 1 2.
  const Scenario four = LoadScenarioText(
      "name: \"t\"\nnodes { name: \"a\" }\nnodes { name: \"b\" }\nnodes { name: \"c\" }\n" +
          blocks + Robots(4),
      "t.textproto");
  EXPECT_EQ(NodeRobots(four), (std::vector<std::vector<int>>{{0, 1}, {2}, {3}}));
  // As many nodes as robots: one each.
  const Scenario one_each = LoadScenarioText(
      "name: \"t\"\nnodes { name: \"a\" }\nnodes { name: \"b\" }\n" + blocks + Robots(2),
      "t.textproto");
  EXPECT_EQ(NodeRobots(one_each), (std::vector<std::vector<int>>{{0}, {1}}));
}

TEST(ScenarioTest, RejectsARobotOnNoNodeAndAnUnknownNode) {
  ExpectRejected("name: \"t\"\nnodes { name: \"n0\" }\nrobot { name: \"a\" node: \"n0\" }\n"
                 "robot { name: \"c\" }\n",
                 "t.textproto:4:1:",
                 "robot \"c\": on no node (the scenario has nodes: give it node: or "
                 "node_assignment: NODE_ASSIGNMENT_BLOCKS)");
  ExpectRejected("name: \"t\"\nnodes { name: \"n0\" }\nnodes { name: \"n1\" }\n"
                 "robot { name: \"c\" node: \"n9\" }\n",
                 "t.textproto:4:19:", "robot \"c\": node \"n9\" is not one of nodes (n0, n1)");
}

TEST(ScenarioTest, RejectsANodeTwiceAndANodeWithNoRobot) {
  ExpectRejected("name: \"t\"\nnodes { name: \"n1\" }\nnodes { name: \"n1\" }\n" + Robots(2),
                 "t.textproto:3:9:", "nodes: \"n1\" twice");
  ExpectRejected("name: \"t\"\nnodes { name: \"n0\" }\nnodes { name: \"n2\" }\n" +
                     Robots(2, " node: \"n0\""),
                 "t.textproto:3:1:", "node \"n2\" has no robot");
  // BLOCKS with more nodes than robots leaves one empty.
  ExpectRejected("name: \"t\"\nnodes { name: \"a\" }\nnodes { name: \"b\" }\n"
                 "node_assignment: NODE_ASSIGNMENT_BLOCKS\n" + Robots(1),
                 "t.textproto:3:1:", "node \"b\" has no robot");
}

TEST(ScenarioTest, RejectsNodeNamesThatAreNotDnsLabels) {
  for (const std::string& name :
       std::vector<std::string>{"N1", "n 1", "n_1", "-n1", "n1-", "", std::string(64, 'n')}) {
    ExpectRejected("name: \"t\"\nnodes { name: \"" + name + "\" }\n" + Robots(1),
                   "t.textproto:2:9:",
                   "node \"" + name + "\": a node name is a DNS label ([a-z0-9-], 1..63");
  }
  const Scenario longest = LoadScenarioText("name: \"t\"\nnodes { name: \"" +
                                                std::string(63, '7') + "\" }\n" +
                                                Robots(1, " node: \"" + std::string(63, '7') + "\""),
                                            "t.textproto");
  EXPECT_EQ(longest.nodes.size(), 1u);
}

TEST(ScenarioTest, RejectsNodeFieldsWithoutNodes) {
  ExpectRejected("name: \"t\"\nrobot { name: \"a\" node: \"n0\" }\n", "t.textproto:2:19:",
                 "robot \"a\": node \"n0\" given, but the scenario has no nodes");
  ExpectRejected("name: \"t\"\nnode_assignment: NODE_ASSIGNMENT_BLOCKS\n" + Robots(1),
                 "t.textproto:2:1:",
                 "node_assignment: NODE_ASSIGNMENT_BLOCKS given, but the scenario has no nodes");
  ExpectRejected("name: \"t\"\nnodes { name: \"n0\" }\nnode_assignment: NODE_ASSIGNMENT_BLOCKS\n"
                 "robot { name: \"a\" node: \"n0\" }\n",
                 "t.textproto:4:19:",
                 "robot \"a\": node given, but node_assignment NODE_ASSIGNMENT_BLOCKS places "
                 "every robot");
}

}  // namespace
}  // namespace sitlnet

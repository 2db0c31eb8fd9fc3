#include "scenario/validation.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

#include "clock/clock.h"
#include "scenario/field_rules.h"
#include "scenario/radio_standard.h"

namespace sitlnet::scenario_internal {
namespace {

bool IsNameChar(char c, bool allow_upper) {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         (allow_upper && c >= 'A' && c <= 'Z');
}

bool IsValidName(const std::string& name, size_t max_length, bool allow_upper) {
  if (name.empty() || name.size() > max_length) return false;
  for (char c : name) {
    if (!IsNameChar(c, allow_upper)) return false;
  }
  return true;
}

std::string Num(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

bool InRange(double value, double low, double high) {
  return std::isfinite(value) && value >= low && value <= high;
}

void ValidateName(const SourceLocator& at, Scenario* scenario) {
  const std::string& name = scenario->spec.name();
  if (!IsValidName(name, kMaxScenarioNameLength, false)) {
    at.Fail({{"name"}}, "scenario name \"" + name + "\" must be 1.." +
                            std::to_string(kMaxScenarioNameLength) +
                            " characters of a-z, 0-9 and '_' (it prefixes every device name)");
  }
  scenario->name = name;
}

void ValidateAirframes(const SourceLocator& at, const proto::Scenario& spec) {
  std::set<std::string> names;
  for (int i = 0; i < spec.airframe_size(); ++i) {
    const proto::Airframe& airframe = spec.airframe(i);
    const std::string who = "airframe \"" + airframe.name() + "\": ";
    if (airframe.name().empty()) at.Fail({{"airframe", i}}, "airframe needs a name");
    if (!names.insert(airframe.name()).second) {
      at.Fail({{"airframe", i}, {"name"}}, who + "duplicate airframe name");
    }
    CheckFieldRules(at, {{"airframe", i}}, who, airframe, spec.radio().standard());
  }
}

const proto::Airframe& FindAirframe(const proto::Scenario& spec, const std::string& name) {
  static const proto::Airframe kDefault;
  for (const proto::Airframe& airframe : spec.airframe()) {
    if (airframe.name() == name) return airframe;
  }
  return kDefault;
}

void ValidateObstacles(const SourceLocator& at, const proto::Scenario& spec) {
  for (int i = 0; i < spec.obstacle_size(); ++i) {
    const proto::Obstacle& box = spec.obstacle(i);
    const std::string who = "obstacle " + std::to_string(i) +
                            (box.name().empty() ? "" : " \"" + box.name() + "\"") + ": ";
    if (!box.has_size_m()) at.Fail({{"obstacle", i}}, who + "size_m is required");
    const double sizes[] = {box.size_m().x(), box.size_m().y(), box.size_m().z()};
    for (double size : sizes) {
      if (!(std::isfinite(size) && size > 0 && size <= 1e5)) {
        at.Fail({{"obstacle", i}, {"size_m"}}, who + "every size_m component must be in (0, 1e5]");
      }
    }
    const double center[] = {box.center_m().x(), box.center_m().y(), box.center_m().z()};
    for (double coordinate : center) {
      if (!InRange(coordinate, -1e6, 1e6)) {
        at.Fail({{"obstacle", i}, {"center_m"}}, who + "center_m must be finite, within 1e6 m");
      }
    }
    CheckFieldRules(at, {{"obstacle", i}}, who, box, spec.radio().standard());
  }
}

// The data mode: rate_mbps for a/b/g, mcs with streams, width and guard interval for n/ac.
void ValidateRadioMode(const SourceLocator& at, const proto::Radio& radio) {
  if (IsHtOrVht(radio.standard()) && radio.has_qos() && !radio.qos()) {
    at.Fail({{"radio"}, {"qos"}},
            "radio: qos false: 802.11n/ac stations are always QoS stations (as in ns-3 3.37)");
  }
  if (!IsHtOrVht(radio.standard())) {
    for (const char* field : {"mcs", "spatial_streams", "channel_width_mhz", "short_guard_interval",
                              "aggregation", "ampdu_max_bytes_be", "ampdu_max_bytes_vi",
                              "ampdu_max_bytes_bk", "ampdu_max_bytes_vo",
                              "minstrel_ht_update_stats_ms"}) {
      const auto* descriptor = radio.GetDescriptor()->FindFieldByName(field);
      if (radio.GetReflection()->HasField(radio, descriptor)) {
        at.Fail({{"radio"}, {field}}, std::string("radio: ") + field +
                                          " applies to STANDARD_80211N_* and STANDARD_80211AC only");
      }
    }
    return;
  }
  if (radio.has_rate_mbps()) {
    at.Fail({{"radio"}, {"rate_mbps"}},
            "radio: rate_mbps applies to 802.11a/b/g; 802.11n/ac send data at mcs");
  }
  if (radio.rate_control() == proto::Radio::RATE_CONTROL_IDEAL) {
    at.Fail({{"radio"}, {"rate_control"}},
            "radio: rate_control RATE_CONTROL_IDEAL is modelled for 802.11a/b/g only");
  }
  // RATE_CONTROL_MINSTREL is Minstrel-HT here, which has neither legacy Minstrel's sampling
  // share nor its interval (ns-3 keeps them for non-HT peers, which an n/ac scenario lacks).
  for (const char* field : {"minstrel_update_stats_ms", "minstrel_look_around_percent"}) {
    const auto* descriptor = radio.GetDescriptor()->FindFieldByName(field);
    if (radio.GetReflection()->HasField(radio, descriptor)) {
      at.Fail({{"radio"}, {field}},
              std::string("radio: ") + field +
                  " applies to 802.11a/b/g Minstrel; 802.11n/ac run Minstrel-HT "
                  "(its interval: minstrel_ht_update_stats_ms)");
    }
  }
  const std::string problem = McsProblem(radio, radio.mcs());
  if (!problem.empty()) {
    // Point at the field the rule is about: the MCS unless the width or streams are at fault.
    const char* field = problem.rfind("channel_width", 0) == 0   ? "channel_width_mhz"
                        : problem.rfind("spatial_streams", 0) == 0 ? "spatial_streams"
                                                                   : "mcs";
    at.Fail({{"radio"}, {field}}, "radio: " + problem);
  }
}

// A path-loss model's parameters are refused under another model: a scenario that sets
// two_ray_system_loss while running 3GPP V2V would otherwise be silently ignored, and its author
// would believe the parameter shaped the run.
void ValidatePathLossParameters(const SourceLocator& at, const proto::Radio& radio) {
  using Model = proto::Radio::PathLossModel;
  constexpr Model kTwoRay = proto::Radio::PATH_LOSS_TWO_RAY_GROUND;
  constexpr Model kUrban = proto::Radio::PATH_LOSS_THREE_GPP_V2V_URBAN;
  constexpr Model kHighway = proto::Radio::PATH_LOSS_THREE_GPP_V2V_HIGHWAY;
  struct Parameter {
    const char* field;
    std::vector<Model> used_by;
  };
  const Parameter parameters[] = {
      {"path_loss_frequency_mhz", {kTwoRay, kUrban, kHighway}},
      {"two_ray_height_above_z_m", {kTwoRay}},
      {"two_ray_system_loss", {kTwoRay}},
      {"two_ray_min_distance_m", {kTwoRay}},
      {"v2v_shadowing", {kUrban, kHighway}},
      {"v2v_truck_percent", {kUrban, kHighway}},
      {"v2v_update_period_ms", {kUrban, kHighway}},
  };
  const google::protobuf::Descriptor* descriptor = radio.GetDescriptor();
  const google::protobuf::Reflection* reflection = radio.GetReflection();
  for (const Parameter& parameter : parameters) {
    const google::protobuf::FieldDescriptor* field = descriptor->FindFieldByName(parameter.field);
    SITLNET_DEMAND(field != nullptr);  // A renamed field in scenario.proto: a bug, not input.
    if (!reflection->HasField(radio, field)) continue;
    const std::vector<Model>& used_by = parameter.used_by;
    if (std::find(used_by.begin(), used_by.end(), radio.path_loss_model()) != used_by.end()) {
      continue;
    }
    std::string models;
    for (size_t i = 0; i < used_by.size(); ++i) {
      models += (i == 0 ? "" : i + 1 == used_by.size() ? " or " : ", ") +
                proto::Radio::PathLossModel_Name(used_by[i]);
    }
    at.Fail({{"radio"}, {parameter.field}},
            "radio: " + std::string(parameter.field) + " applies to path_loss_model " + models +
                " only, not " + proto::Radio::PathLossModel_Name(radio.path_loss_model()));
  }
}

// Minstrel's parameters are refused under another rate control (as path-loss parameters are).
void ValidateMinstrelParameters(const SourceLocator& at, const proto::Radio& radio) {
  if (radio.rate_control() == proto::Radio::RATE_CONTROL_MINSTREL) {
    // ns-3's Minstrel never gives up on a frame whose RTS fails (it leaves that to the queue's
    // MaxDelay): with frames that never expire, one unreachable receiver would hold its queue.
    if (radio.rts_threshold_bytes() > 0 && radio.queue_max_delay_ms() == 0) {
      at.Fail({{"radio"}, {"queue_max_delay_ms"}},
              "radio: queue_max_delay_ms 0 (frames never expire) with RTS/CTS and "
              "RATE_CONTROL_MINSTREL: Minstrel retries a frame whose RTS fails until it "
              "expires; give queue_max_delay_ms a bound");
    }
    return;
  }
  for (const char* field : {"minstrel_update_stats_ms", "minstrel_look_around_percent",
                            "minstrel_ewma_percent", "minstrel_sample_columns",
                            "minstrel_packet_bytes", "minstrel_ht_update_stats_ms"}) {
    const google::protobuf::FieldDescriptor* descriptor =
        radio.GetDescriptor()->FindFieldByName(field);
    SITLNET_DEMAND(descriptor != nullptr);  // A renamed field in scenario.proto: a bug.
    if (!radio.GetReflection()->HasField(radio, descriptor)) continue;
    at.Fail({{"radio"}, {field}}, "radio: " + std::string(field) +
                                      " applies to rate_control RATE_CONTROL_MINSTREL only");
  }
}

// Under a Block Ack agreement a frame has no retry limit: only its expiry ends the BlockAckReqs
// for it (ns-3 3.37's MissedBlockAck; its MaxDelay cannot be "never"). With frames that never
// expire, one unreachable receiver would hold its access category for ever.
void ValidateAggregationExpiry(const SourceLocator& at, const proto::Radio& radio) {
  if (radio.aggregation() && radio.queue_max_delay_ms() == 0) {
    at.Fail({{"radio"}, {"queue_max_delay_ms"}},
            "radio: queue_max_delay_ms 0 (frames never expire) with aggregation: under a Block "
            "Ack agreement a frame is requested again until it expires; give queue_max_delay_ms "
            "a bound");
  }
}

// Ranges and rates come from the fields' options (field_rules.h); what follows relates fields.
void ValidateRadio(const SourceLocator& at, const proto::Radio& radio) {
  CheckFieldRules(at, {{"radio"}}, "radio: ", radio, radio.standard());
  ValidateMinstrelParameters(at, radio);
  ValidateAggregationExpiry(at, radio);
  if (radio.short_slot() && radio.standard() != proto::Radio::STANDARD_80211G) {
    at.Fail({{"radio"}, {"short_slot"}}, "radio: short_slot applies to STANDARD_80211G only");
  }
  if (radio.nakagami_fading() &&
      (radio.nakagami_m0() < 0.5 || radio.nakagami_m1() < 0.5 || radio.nakagami_m2() < 0.5)) {
    at.Fail({{"radio"}, {"nakagami_m0"}}, "radio: nakagami_m0/m1/m2 must be >= 0.5");
  }
  if (!(radio.nakagami_d1_m() > 0 && radio.nakagami_d2_m() >= radio.nakagami_d1_m())) {
    at.Fail({{"radio"}, {"nakagami_d1_m"}}, "radio: need 0 < nakagami_d1_m <= nakagami_d2_m");
  }
  // ns-3 would chain both, but they model the same multipath: each frame would fade twice.
  if (radio.jakes_fading() && radio.nakagami_fading()) {
    at.Fail({{"radio"}, {"jakes_fading"}},
            "radio: jakes_fading and nakagami_fading both model fast fading; set one");
  }
  if (radio.jakes_doppler_from_speed() && !radio.jakes_fading()) {
    at.Fail({{"radio"}, {"jakes_doppler_from_speed"}},
            "radio: jakes_doppler_from_speed needs jakes_fading");
  }
  ValidateRadioMode(at, radio);
  ValidatePathLossParameters(at, radio);
}

void ValidateTiming(const SourceLocator& at, Scenario* scenario) {
  const proto::Timing& timing = scenario->spec.timing();
  // Each step and the duration: positive and bounded, by their options (field_rules.h).
  CheckFieldRules(at, {{"timing"}}, "timing: ", timing, scenario->spec.radio().standard());
  const std::pair<const char*, int64_t> steps[] = {{"physics_step_us", timing.physics_step_us()},
                                                   {"network_step_us", timing.network_step_us()}};
  for (const auto& [field, step] : steps) {
    if (timing.iteration_us() % step != 0) {
      at.Fail({{"timing"}, {field}},
              std::string("timing: iteration_us ") + std::to_string(timing.iteration_us()) +
                  " is not a whole multiple of " + field + " " + std::to_string(step));
    }
  }
  if (const std::string why = clock::CheckRealtimeFactor(timing.realtime_factor()); !why.empty()) {
    at.Fail({{"timing"}, {"realtime_factor"}}, "timing: " + why);
  }
  // 0: off; at most 1 kHz of virtual time (ROS 2 simulators publish /clock at 100 Hz to 1 kHz).
  if (!(timing.ros2_clock_hz() == 0 ||
        (timing.ros2_clock_hz() > 0 && timing.ros2_clock_hz() <= kMaxRos2ClockHz))) {
    at.Fail({{"timing"}, {"ros2_clock_hz"}},
            "timing: ros2_clock_hz " + std::to_string(timing.ros2_clock_hz()) +
                " must be 0 (off) or in (0, " + std::to_string(kMaxRos2ClockHz) + "]");
  }
  scenario->iteration_ns = timing.iteration_us() * kNsPerUs;
  scenario->physics_step_ns = timing.physics_step_us() * kNsPerUs;
  scenario->network_step_ns = timing.network_step_us() * kNsPerUs;
  scenario->duration_ns = timing.duration_ms() * kNsPerMs;
  scenario->physics_steps_per_iteration =
      static_cast<int>(timing.iteration_us() / timing.physics_step_us());
  scenario->network_steps_per_iteration =
      static_cast<int>(timing.iteration_us() / timing.network_step_us());
}

Ipv4Prefix ParsePrefixField(const SourceLocator& at, const char* field, const std::string& text) {
  const auto prefix = ParseIpv4Prefix(text);
  if (!prefix || prefix->length < 8 || prefix->length > 30) {
    at.Fail({{"addresses"}, {field}}, std::string("addresses: ") + field + " \"" + text +
                                          "\" must be an IPv4 prefix a.b.c.d/8../30 with no "
                                          "host bits set");
  }
  return *prefix;
}

void ValidateAddresses(const SourceLocator& at, Scenario* scenario) {
  const proto::AddressPlan& plan = scenario->spec.addresses();
  scenario->wlan_subnet = ParsePrefixField(at, "wlan_subnet", plan.wlan_subnet());
  scenario->ctl_subnet = ParsePrefixField(at, "ctl_subnet", plan.ctl_subnet());
  if (scenario->wlan_subnet.Overlaps(scenario->ctl_subnet)) {
    // Point at whichever of the two the file sets.
    const char* field = plan.has_ctl_subnet() ? "ctl_subnet" : "wlan_subnet";
    at.Fail({{"addresses"}, {field}}, "addresses: ctl_subnet " + plan.ctl_subnet() +
                                          " overlaps wlan_subnet " + plan.wlan_subnet());
  }
  const uint64_t robots = scenario->spec.robot_size();
  if (scenario->wlan_subnet.Size() - 2 < robots) {
    at.Fail({{"addresses"}, {"wlan_subnet"}}, "addresses: wlan_subnet " + plan.wlan_subnet() +
                                                  " has no room for " + std::to_string(robots) +
                                                  " robots");
  }
  if (scenario->ctl_subnet.Size() / 4 < robots) {
    at.Fail({{"addresses"}, {"ctl_subnet"}}, "addresses: ctl_subnet " + plan.ctl_subnet() +
                                                 " has room for " +
                                                 std::to_string(scenario->ctl_subnet.Size() / 4) +
                                                 " /30 pairs, not " + std::to_string(robots));
  }
  if (plan.txqueuelen() < 1) at.Fail({{"addresses"}, {"txqueuelen"}}, "txqueuelen must be >= 1");
  if (plan.physics_port() < 1 || plan.physics_port() > 65535) {
    at.Fail({{"addresses"}, {"physics_port"}}, "addresses: physics_port must be in [1, 65535]");
  }
}

void ValidateGeodeticOrigin(const SourceLocator& at, const proto::Scenario& spec) {
  if (!spec.has_geodetic_origin()) return;
  const proto::GeodeticOrigin& origin = spec.geodetic_origin();
  const auto check = [&](const char* field, double value, double low, double high,
                         const char* why) {
    // Open at the poles: the ENU frame's east and north are undefined there.
    if (!InRange(value, low, high)) {
      at.Fail({{"geodetic_origin"}, {field}},
              std::string("geodetic_origin: ") + field + " " + Num(value) + " out of range " + why);
    }
  };
  check("latitude_deg", origin.latitude_deg(), -89.9, 89.9,
        "[-89.9, 89.9] (east and north are undefined at the poles)");
  check("longitude_deg", origin.longitude_deg(), -180, 180, "[-180, 180]");
  // The ISA formula the barometer uses holds in the troposphere, below 11 km: 2 km above the
  // highest origin are left for flight.
  check("altitude_m", origin.altitude_m(), -1000, 9000,
        "[-1000, 9000] (the barometer's ISA troposphere ends at 11 km)");
  if ((origin.has_latitude_deg() || origin.has_longitude_deg()) && !origin.has_magnetic_field()) {
    at.Fail(
        {{"geodetic_origin"}},
        "geodetic_origin: a latitude/longitude other than the default needs magnetic_field "
        "(declination_deg, inclination_deg, intensity_gauss of the World Magnetic Model there)");
  }
  const proto::MagneticField& field = origin.magnetic_field();
  const auto check_field = [&](const char* name, double value, double low, double high,
                               const char* range) {
    if (!InRange(value, low, high)) {
      at.Fail({{"geodetic_origin"}, {"magnetic_field"}, {name}},
              std::string("geodetic_origin: magnetic_field ") + name + " " + Num(value) +
                  " out of range " + range);
    }
  };
  check_field("declination_deg", field.declination_deg(), -180, 180, "[-180, 180]");
  check_field("inclination_deg", field.inclination_deg(), -90, 90, "[-90, 90]");
  // WMM2025 at sea level, 2026.0, over a 1-degree grid: 0.2205 to 0.6694 gauss.
  check_field("intensity_gauss", field.intensity_gauss(), 0.1, 1, "[0.1, 1]");
}

// GPS, barometer and magnetometer figures of robot `i` beyond their declared ranges.
void ValidateHilSensors(const SourceLocator& at, int i, const proto::Robot& robot) {
  const std::string who = "robot \"" + robot.name() + "\": ";
  const std::tuple<const char*, const char*, double> noises[] = {
      {"gps", "horizontal_noise_m", robot.gps().horizontal_noise_m()},
      {"gps", "vertical_noise_m", robot.gps().vertical_noise_m()},
      {"gps", "velocity_noise_m_s", robot.gps().velocity_noise_m_s()},
      {"barometer", "noise_pa", robot.barometer().noise_pa()},
      {"magnetometer", "noise_gauss", robot.magnetometer().noise_gauss()}};
  for (const auto& [block, field, value] : noises) {
    if (!InRange(value, 0, 1e6)) {
      at.Fail({{"robot", i}, {block}, {field}},
              who + block + " " + field + " " + Num(value) + " must be finite and >= 0");
    }
  }
  if (robot.gps().satellites() > 254) {
    at.Fail({{"robot", i}, {"gps"}, {"satellites"}},
            who + "gps satellites must be <= 254 (255 means unknown in HIL_GPS)");
  }
}

// A robot's own rate (a/b/g) or MCS (n/ac), checked against the scenario's radio.
void ValidateRobotRadio(const SourceLocator& at, int i, const proto::Robot& robot,
                        const proto::Radio& radio) {
  const std::string who = "robot \"" + robot.name() + "\": ";
  const bool ht = IsHtOrVht(radio.standard());
  if (ht && robot.has_rate_mbps()) {
    at.Fail({{"robot", i}, {"rate_mbps"}},
            who + "rate_mbps applies to 802.11a/b/g; 802.11n/ac send data at mcs");
  }
  if (!robot.has_mcs()) return;
  if (!ht) {
    at.Fail({{"robot", i}, {"mcs"}}, who + "mcs applies to STANDARD_80211N_* and STANDARD_80211AC only");
    return;  // One line for one field: the rules below are about n/ac.
  }
  const std::string problem = McsProblem(radio, robot.mcs());
  if (!problem.empty()) at.Fail({{"robot", i}, {"mcs"}}, who + problem);
  if (radio.rate_control() == proto::Radio::RATE_CONTROL_MINSTREL) {
    at.Fail({{"robot", i}, {"mcs"}},
            who + "mcs would be ignored: Minstrel-HT (rate_control RATE_CONTROL_MINSTREL) "
                  "chooses every robot's MCS");
  }
}

void ValidateAndDeriveRobots(const SourceLocator& at, Scenario* scenario) {
  const proto::Scenario& spec = scenario->spec;
  if (spec.robot_size() == 0) at.Fail({}, "a scenario needs at least one robot");
  if (spec.robot_size() > kMaxRobots) {
    at.Fail({{"robot", kMaxRobots}}, "at most " + std::to_string(kMaxRobots) + " robots");
  }
  std::set<std::string> names;
  std::set<Ipv4> wlan_addresses;
  for (int i = 0; i < spec.robot_size(); ++i) {
    const proto::Robot& robot = spec.robot(i);
    const std::string who = "robot \"" + robot.name() + "\": ";
    if (!IsValidName(robot.name(), kMaxRobotNameLength, true)) {
      at.Fail({{"robot", i}, {"name"}}, who + "name must be 1.." +
                                            std::to_string(kMaxRobotNameLength) +
                                            " characters of A-Z, a-z, 0-9 and '_'");
    }
    if (!names.insert(robot.name()).second) {
      at.Fail({{"robot", i}, {"name"}}, who + "duplicate robot name");
    }
    const double position[] = {robot.position_m().x(), robot.position_m().y(),
                               robot.position_m().z()};
    for (double coordinate : position) {
      if (!InRange(coordinate, -1e6, 1e6)) {
        at.Fail({{"robot", i}, {"position_m"}}, who + "position_m must be finite, within 1e6 m");
      }
    }
    // Declared ranges and rates: ports, the failsafe, the radio overrides' (same_rules_as),
    // lidar, IMU and GPS figures.
    CheckFieldRules(at, {{"robot", i}}, who, robot, spec.radio().standard());
    if (robot.ground_station() && (robot.px4_sim_port() != 0 || robot.ardupilot_json_port() != 0)) {
      at.Fail({{"robot", i}, {"ground_station"}},
              who + "is a ground station: it has no physics for an autopilot to fly");
    }
    if (robot.px4_sim_port() != 0 && robot.ardupilot_json_port() != 0) {
      at.Fail({{"robot", i}, {"px4_sim_port"}},
              who + "has both ardupilot_json_port and px4_sim_port: one autopilot per robot");
    }
    ValidateHilSensors(at, i, robot);
    ValidateRobotRadio(at, i, robot, spec.radio());
    if (!robot.airframe().empty() && FindAirframe(spec, robot.airframe()).name().empty()) {
      at.Fail({{"robot", i}, {"airframe"}}, who + "unknown airframe \"" + robot.airframe() + "\"");
    }
    RobotPlan plan;
    plan.index = i;
    plan.name = robot.name();
    plan.netns = RobotNetnsName(scenario->name, robot.name());
    plan.root_veth = RobotRootVethName(scenario->name, i);
    plan.wlan_mac = RobotMac(i);
    plan.wlan_address = Ipv4{scenario->wlan_subnet.network.host_order + 1 + uint32_t(i)};
    if (robot.has_wlan_address()) {
      const auto address = ParseIpv4(robot.wlan_address());
      if (!address || !scenario->wlan_subnet.Contains(*address) ||
          *address == scenario->wlan_subnet.network ||
          *address == scenario->wlan_subnet.Broadcast()) {
        at.Fail({{"robot", i}, {"wlan_address"}}, who + "wlan_address \"" + robot.wlan_address() +
                                                      "\" is not a host address of " +
                                                      FormatIpv4Prefix(scenario->wlan_subnet));
      }
      plan.wlan_address = *address;
    }
    if (!wlan_addresses.insert(plan.wlan_address).second) {
      at.Fail({{"robot", i}}, who + "wlan address " + FormatIpv4(plan.wlan_address) +
                                  " is already used by another robot");
    }
    const uint32_t pair_base = scenario->ctl_subnet.network.host_order + 4 * uint32_t(i);
    plan.ctl_root_address = Ipv4{pair_base + 1};
    plan.ctl_robot_address = Ipv4{pair_base + 2};
    plan.spec = robot;
    plan.airframe = FindAirframe(spec, robot.airframe());
    scenario->robots.push_back(std::move(plan));
  }
}

// A DNS label (RFC 1123 2.1): a-z, 0-9 and '-', 1..63, no '-' at either end. A node's name
// is its pod's hostname, so a StatefulSet pod can pass `--node "$(hostname)"`.
bool IsDnsLabel(const std::string& name) {
  if (name.empty() || name.size() > static_cast<size_t>(kMaxNodeNameLength)) return false;
  if (name.front() == '-' || name.back() == '-') return false;
  for (char c : name) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-')) return false;
  }
  return true;
}

std::string NodeNames(const std::vector<NodePlan>& nodes) {
  std::string names;
  for (const NodePlan& node : nodes) names += (names.empty() ? "" : ", ") + node.name;
  return names;
}

// The node of robot `i` under NODE_ASSIGNMENT_EXPLICIT: the one its `node` field names.
int ExplicitNode(const SourceLocator& at, const Scenario& scenario, int i) {
  const proto::Robot& robot = scenario.spec.robot(i);
  const std::string who = "robot \"" + robot.name() + "\": ";
  if (!robot.has_node()) {
    at.Fail({{"robot", i}}, who +
                                "on no node (the scenario has nodes: give it node: or "
                                "node_assignment: NODE_ASSIGNMENT_BLOCKS)");
  }
  const int node = scenario.NodeIndex(robot.node());
  if (node < 0) {
    at.Fail({{"robot", i}, {"node"}}, who + "node \"" + robot.node() + "\" is not one of nodes (" +
                                          NodeNames(scenario.nodes) + ")");
  }
  return node;
}

// Nodes (issue 35): names, then each robot's node, then every node must run a robot.
void ValidateAndDeriveNodes(const SourceLocator& at, Scenario* scenario) {
  const proto::Scenario& spec = scenario->spec;
  const bool blocks = spec.node_assignment() == proto::Scenario::NODE_ASSIGNMENT_BLOCKS;
  if (spec.nodes_size() == 0) {
    for (int i = 0; i < spec.robot_size(); ++i) {
      if (spec.robot(i).has_node()) {
        at.Fail({{"robot", i}, {"node"}}, "robot \"" + spec.robot(i).name() + "\": node \"" +
                                              spec.robot(i).node() +
                                              "\" given, but the scenario has no nodes");
      }
    }
    if (blocks) {
      at.Fail({{"node_assignment"}},
              "node_assignment: NODE_ASSIGNMENT_BLOCKS given, but the scenario has no nodes");
    }
    return;
  }
  for (int j = 0; j < spec.nodes_size(); ++j) {
    const std::string& name = spec.nodes(j).name();
    if (!IsDnsLabel(name)) {
      at.Fail({{"nodes", j}, {"name"}},
              "node \"" + name + "\": a node name is a DNS label ([a-z0-9-], 1.." +
                  std::to_string(kMaxNodeNameLength) + ", no '-' at either end)");
    }
    if (scenario->NodeIndex(name) >= 0) {
      at.Fail({{"nodes", j}, {"name"}}, "nodes: \"" + name + "\" twice");
    }
    scenario->nodes.push_back(NodePlan{name, {}});
  }
  const int64_t robots = spec.robot_size();
  const int64_t nodes = spec.nodes_size();
  for (int i = 0; i < spec.robot_size(); ++i) {
    if (blocks && spec.robot(i).has_node()) {
      at.Fail({{"robot", i}, {"node"}},
              "robot \"" + spec.robot(i).name() +
                  "\": node given, but node_assignment NODE_ASSIGNMENT_BLOCKS places every robot");
    }
    const int node = blocks ? static_cast<int>(i * nodes / robots) : ExplicitNode(at, *scenario, i);
    scenario->robots[i].node = node;
    scenario->nodes[node].robots.push_back(i);  // i ascends, so each list does.
  }
  for (int j = 0; j < spec.nodes_size(); ++j) {
    if (scenario->nodes[j].robots.empty()) {
      at.Fail({{"nodes", j}}, "node \"" + scenario->nodes[j].name + "\" has no robot");
    }
  }
}

}  // namespace

void ValidateAndDerive(const SourceLocator& locator, Scenario* scenario) {
  ValidateName(locator, scenario);
  if (scenario->spec.silent_robot_timeout_ms() <= 0 ||
      scenario->spec.silent_robot_timeout_ms() > kMaxDurationMs) {
    locator.Fail({{"silent_robot_timeout_ms"}},
                 "silent_robot_timeout_ms must be in [1, " + std::to_string(kMaxDurationMs) + "]");
  }
  ValidateAirframes(locator, scenario->spec);
  ValidateObstacles(locator, scenario->spec);
  ValidateRadio(locator, scenario->spec.radio());
  ValidateTiming(locator, scenario);
  ValidateGeodeticOrigin(locator, scenario->spec);
  ValidateAddresses(locator, scenario);
  ValidateAndDeriveRobots(locator, scenario);
  ValidateAndDeriveNodes(locator, scenario);
}

}  // namespace sitlnet::scenario_internal

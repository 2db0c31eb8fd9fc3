#include "robot_images/flocker/flocker_options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>

namespace sitlnet::flocker {
namespace {

constexpr char kUsage[] =
    "usage: flocker [--target X,Y] [--altitude-m Z] [--broadcast-hz F] [--neighbour-timeout-s T]\n"
    "               [--beacon-port P] [--device DEV] [--tos T] [--airframe TEXTPROTO]\n"
    "               [--lidar-fov-deg D] [--obstacle-gap-m G] [--log-period-s S] [VAT parameter flags]\n"
    "--tos T: the beacons' IPv4 TOS byte, 0-255, decimal or 0x hex (default 0); on QoS radios\n"
    "  its top three bits are the 802.11 user priority: 0xc0 is voice, 0 best effort.\n"
    "VAT parameter flags (symbols of docs/case-study.md; defaults there):\n"
    "  --flock-speed-m-s (v_flock) --max-speed-m-s (v_max) --migration-speed-m-s (v_mig)\n"
    "  --repulsion-range-m (r0_rep) --repulsion-gain (p_rep) --attraction-range-m (r0_att)\n"
    "  --attraction-gain (p_att) --friction-range-m (r0_frict) --friction-coefficient (C_frict)\n"
    "  --friction-slack-m-s (v_frict) --friction-accel-m-s2 (a_frict) --friction-gain (p_frict)\n"
    "  --shill-range-m (r0_shill) --shill-speed-m-s (v_shill) --shill-accel-m-s2 (a_shill)\n"
    "  --shill-gain (p_shill)\n"
    "Runs inside a robot namespace; needs SITLNET_PHYSICS_ADDR and SITLNET_ROBOT_INDEX.\n";

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "flocker: %s\n", message.c_str());
  std::exit(2);
}

double ParseNumber(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value)) {
    Die(flag + ": \"" + text + "\" is not a number");
  }
  return value;
}

// Flags that set one number, by name.
std::map<std::string, double*> NumberFlags(Options* o) {
  FlockingParams& p = o->flocking;
  return {
      {"--altitude-m", &o->altitude_m},
      {"--broadcast-hz", &o->broadcast_hz},
      {"--neighbour-timeout-s", &o->neighbour_timeout_s},
      {"--lidar-fov-deg", &o->lidar_fov_deg},
      {"--obstacle-gap-m", &o->obstacle_gap_m},
      {"--log-period-s", &o->log_period_s},
      {"--flock-speed-m-s", &p.flock_speed_m_s},
      {"--max-speed-m-s", &p.max_speed_m_s},
      {"--migration-speed-m-s", &p.migration_speed_m_s},
      {"--repulsion-range-m", &p.repulsion_range_m},
      {"--repulsion-gain", &p.repulsion_gain_1_s},
      {"--attraction-range-m", &p.attraction_range_m},
      {"--attraction-gain", &p.attraction_gain_1_s},
      {"--friction-range-m", &p.friction_range_m},
      {"--friction-coefficient", &p.friction_coefficient},
      {"--friction-slack-m-s", &p.friction_slack_m_s},
      {"--friction-accel-m-s2", &p.friction_accel_m_s2},
      {"--friction-gain", &p.friction_gain_1_s},
      {"--shill-range-m", &p.shill_range_m},
      {"--shill-speed-m-s", &p.shill_speed_m_s},
      {"--shill-accel-m-s2", &p.shill_accel_m_s2},
      {"--shill-gain", &p.shill_gain_1_s},
  };
}

}  // namespace

Options ParseOptions(int argc, char** argv) {
  Options options;
  const std::map<std::string, double*> numbers = NumberFlags(&options);
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (i + 1 >= argc) Die(flag + " needs a value\n" + kUsage);
    const char* value = argv[++i];
    if (const auto number = numbers.find(flag); number != numbers.end()) {
      *number->second = ParseNumber(flag, value);
    } else if (flag == "--target") {
      double x, y;
      char extra;
      if (std::sscanf(value, "%lf,%lf%c", &x, &y, &extra) != 2) Die("--target wants X,Y");
      options.target_m = {x, y};
    } else if (flag == "--beacon-port") {
      const double port = ParseNumber(flag, value);
      if (port < 1 || port > 65535 || port != std::floor(port)) Die("--beacon-port: 1..65535");
      options.beacon_port = static_cast<uint16_t>(port);
    } else if (flag == "--tos") {
      char* end = nullptr;
      // Base 16 after "0x", else 10: "010" is ten, not octal eight.
      const bool hex = value[0] == '0' && (value[1] == 'x' || value[1] == 'X');
      const long tos = std::strtol(value, &end, hex ? 16 : 10);
      if (end == value || *end != '\0' || tos < 0 || tos > 255) {
        Die(std::string("--tos: \"") + value + "\" is not a TOS byte (0-255, decimal or 0x hex)");
      }
      options.tos = static_cast<int>(tos);
    } else if (flag == "--device") {
      options.device = value;
    } else if (flag == "--airframe") {
      options.airframe_text = value;
    } else {
      Die("unknown flag " + flag + "\n" + kUsage);
    }
  }
  // Bounds that keep the periods in nanoseconds within int64 (main converts them).
  if (!(options.broadcast_hz >= 1e-3)) Die("--broadcast-hz must be at least 0.001");
  for (const auto& [flag, seconds] :
       {std::pair{"--neighbour-timeout-s", options.neighbour_timeout_s},
        std::pair{"--log-period-s", options.log_period_s}}) {
    if (!(seconds >= 0 && seconds <= 1e6)) Die(std::string(flag) + " must be in [0, 1e6]");
  }
  if (options.flocking.max_speed_m_s <= 0) Die("--max-speed-m-s must be > 0");
  return options;
}

}  // namespace sitlnet::flocker

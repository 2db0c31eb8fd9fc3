#include "view/autopilot_mode.h"

#include <array>
#include <string_view>

namespace sitlnet::view {
namespace {

// PX4_CUSTOM_MAIN_MODE, from 1.
constexpr std::array<std::string_view, 9> kPx4MainModes = {
    "MANUAL", "ALTCTL", "POSCTL", "AUTO", "ACRO", "OFFBOARD", "STABILIZED", "RATTITUDE", "SIMPLE"};
constexpr uint32_t kPx4MainAuto = 4;
constexpr uint32_t kPx4MainPosctl = 3;
// PX4_CUSTOM_SUB_MODE_AUTO, from 1 (7 is reserved: it was RTGS).
constexpr std::array<std::string_view, 10> kPx4AutoSubModes = {
    "READY", "TAKEOFF", "LOITER",        "MISSION",  "RTL",
    "LAND",  "",        "FOLLOW_TARGET", "PRECLAND", "VTOL_TAKEOFF"};
// PX4_CUSTOM_SUB_MODE_POSCTL, from 0.
constexpr std::array<std::string_view, 2> kPx4PosctlSubModes = {"", "ORBIT"};

std::string Px4ModeName(uint32_t custom_mode) {
  const uint32_t main = (custom_mode >> 16) & 0xff;
  const uint32_t sub = (custom_mode >> 24) & 0xff;
  const auto unnamed = [&] {
    return "PX4 main " + std::to_string(main) + " sub " + std::to_string(sub);
  };
  if (main < 1 || main > kPx4MainModes.size()) return unnamed();
  std::string name(kPx4MainModes[main - 1]);
  std::string_view sub_name;
  if (main == kPx4MainAuto) {
    if (sub < 1 || sub > kPx4AutoSubModes.size()) return unnamed();
    sub_name = kPx4AutoSubModes[sub - 1];
    if (sub_name.empty()) return unnamed();
  } else if (main == kPx4MainPosctl) {
    if (sub >= kPx4PosctlSubModes.size()) return unnamed();
    sub_name = kPx4PosctlSubModes[sub];
  } else if (sub != 0) {
    return unnamed();
  }
  if (!sub_name.empty()) name += "." + std::string(sub_name);
  return name;
}

// COPTER_MODE by number; empty where the enum has no entry.
constexpr std::array<std::string_view, 29> kCopterModes = {
    "STABILIZE", "ACRO",     "ALT_HOLD", "AUTO",   "GUIDED",   "LOITER",     "RTL",
    "CIRCLE",    "",         "LAND",     "",       "DRIFT",    "",           "SPORT",
    "FLIP",      "AUTOTUNE", "POSHOLD",  "BRAKE",  "THROW",    "AVOID_ADSB", "GUIDED_NOGPS",
    "SMART_RTL", "FLOWHOLD", "FOLLOW",   "ZIGZAG", "SYSTEMID", "AUTOROTATE", "AUTO_RTL",
    "TURTLE"};

// MAV_TYPE values that ArduCopter (multirotors and helicopters) reports.
bool IsCopterType(uint8_t mav_type) {
  switch (mav_type) {
    case 2:   // QUADROTOR
    case 3:   // COAXIAL
    case 4:   // HELICOPTER
    case 13:  // HEXAROTOR
    case 14:  // OCTOROTOR
    case 15:  // TRICOPTER
    case 29:  // DODECAROTOR
    case 35:  // DECAROTOR
      return true;
    default:
      return false;
  }
}

std::string ArduPilotModeName(const mavlink::Heartbeat& heartbeat) {
  const uint32_t mode = heartbeat.custom_mode;
  if (IsCopterType(heartbeat.type) && mode < kCopterModes.size() && !kCopterModes[mode].empty()) {
    return std::string(kCopterModes[mode]);
  }
  return "ArduPilot mode " + std::to_string(mode);
}

}  // namespace

std::string AutopilotModeName(const mavlink::Heartbeat& heartbeat) {
  if (heartbeat.autopilot == kMavAutopilotPx4) return Px4ModeName(heartbeat.custom_mode);
  if (heartbeat.autopilot == kMavAutopilotArduPilot) return ArduPilotModeName(heartbeat);
  return {};
}

}  // namespace sitlnet::view

// The name of the flight mode an autopilot reports in its MAVLink HEARTBEAT (custom_mode), for
// PX4 and ArduCopter. The numbers are the autopilots' own: PX4 v1.14's px4_custom_mode.h (main
// mode in bits 16-23, sub mode in bits 24-31) and ArduPilot's COPTER_MODE (ardupilotmega.xml).
#ifndef SITLNET_VIEW_AUTOPILOT_MODE_H_
#define SITLNET_VIEW_AUTOPILOT_MODE_H_

#include <cstdint>
#include <string>

#include "mavlink/mavlink.h"

namespace sitlnet::view {

inline constexpr uint8_t kMavAutopilotArduPilot = 3;  // MAV_AUTOPILOT_ARDUPILOTMEGA
inline constexpr uint8_t kMavAutopilotPx4 = 12;       // MAV_AUTOPILOT_PX4

// "AUTO.LOITER", "POSCTL", ... for PX4; "GUIDED", "LAND", ... for an ArduPilot multirotor or
// helicopter; "PX4 main 11 sub 0" or "ArduPilot mode 99" for a number the tables do not
// name (another vehicle of ArduPilot's, a newer mode). Empty for a HEARTBEAT of neither
// autopilot (a ground station's, MAV_AUTOPILOT_INVALID).
std::string AutopilotModeName(const mavlink::Heartbeat& heartbeat);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_AUTOPILOT_MODE_H_

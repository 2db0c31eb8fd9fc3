// Command-line options of the flocker image (usage: `flocker --help`).
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKER_OPTIONS_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKER_OPTIONS_H_

#include <cstdint>
#include <string>

#include "robot_images/flocker/flocking.h"

namespace sitlnet::flocker {

struct Options {
  Vec2 target_m{0, 0};
  double altitude_m = 5;
  double broadcast_hz = 10;
  double neighbour_timeout_s = 2;  // tau
  uint16_t beacon_port = 47000;
  std::string device = "wlan0";
  // IPv4 TOS byte of the beacons (IP_TOS). On QoS radios (802.11n/ac, or a/b/g with radio.qos)
  // its top three bits are the user priority, so 0xc0 sends them at voice (docs/howto-qos.md).
  int tos = 0;
  std::string airframe_text;  // proto Airframe in text format; empty: defaults
  double lidar_fov_deg = 360;
  // Adjacent lidar hits further apart than this belong to different obstacles.
  double obstacle_gap_m = 3;
  double log_period_s = 1;
  FlockingParams flocking;
};

// Parses argv; prints usage and exits 0 on --help, prints one line naming
// the flag and exits 2 on a bad or unknown flag.
Options ParseOptions(int argc, char** argv);

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKER_OPTIONS_H_

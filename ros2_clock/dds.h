// The Cyclone DDS side of /clock, shared by the publisher and the echo tool (not part of the
// module's public header: only these two programs link Cyclone DDS).
#ifndef SITLNET_ROS2_CLOCK_DDS_H_
#define SITLNET_ROS2_CLOCK_DDS_H_

#include <dds/dds.h>

#include <cstdint>

#include "Clock.h"

namespace sitlnet::ros2_clock {

// A participant of `domain_id` on the loopback interface only (LoopbackOnlyCycloneConfig), the
// /clock topic, and the QoS that ROS 2's time source subscribes with (rclcpp's ClockQoS: the
// sensor-data profile, best effort and volatile, keep last 1). Exits the process with one line
// on stderr if Cyclone DDS refuses.
struct ClockTopic {
  explicit ClockTopic(uint32_t domain_id);
  ~ClockTopic();
  ClockTopic(const ClockTopic&) = delete;
  ClockTopic& operator=(const ClockTopic&) = delete;

  dds_entity_t participant = 0;
  dds_entity_t topic = 0;
  dds_qos_t* qos = nullptr;
};

// Exits with status 2 and "<program>: <what>: <Cyclone's reason>" when `result` < 0.
void ExitIfDdsError(dds_return_t result, const char* program, const char* what);

}  // namespace sitlnet::ros2_clock

#endif  // SITLNET_ROS2_CLOCK_DDS_H_

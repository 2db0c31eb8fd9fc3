// ClockTopic: a loopback-only Cyclone DDS participant with ROS 2's /clock topic and QoS.
#include "ros2_clock/dds.h"

#include <cstdio>
#include <cstdlib>

#include "ros2_clock/ros2_clock.h"

namespace sitlnet::ros2_clock {

void ExitIfDdsError(dds_return_t result, const char* program, const char* what) {
  if (result >= 0) return;
  std::fprintf(stderr, "%s: %s: %s\n", program, what, dds_strretcode(result));
  std::exit(2);
}

ClockTopic::ClockTopic(uint32_t domain_id) {
  const std::string config = LoopbackOnlyCycloneConfig();
  ExitIfDdsError(dds_create_domain(domain_id, config.c_str()), "ros2_clock", "create domain");
  participant = dds_create_participant(domain_id, nullptr, nullptr);
  ExitIfDdsError(participant, "ros2_clock", "create participant");
  topic = dds_create_topic(participant, &rosgraph_msgs_msg_dds__Clock__desc, kTopicName, nullptr,
                           nullptr);
  ExitIfDdsError(topic, "ros2_clock", "create topic rt/clock");
  qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
}

ClockTopic::~ClockTopic() {
  dds_delete_qos(qos);
  dds_delete(participant);
}

}  // namespace sitlnet::ros2_clock

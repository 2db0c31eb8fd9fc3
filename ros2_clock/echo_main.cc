// ros2_clock_echo: a /clock subscriber with the IDL and QoS that ROS 2 uses, for tests and for
// checking a robot by hand: prints "clock SEC.NANOSEC" per message received and exits 0 after
// --count messages, 1 if they do not come within --timeout-s seconds (of the host's clock).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ros2_clock/dds.h"

int main(int argc, char** argv) {
  int count = 10;
  double timeout_s = 10;
  uint32_t domain = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--count") {
      count = std::atoi(argv[i + 1]);
    } else if (flag == "--timeout-s") {
      timeout_s = std::atof(argv[i + 1]);
    } else if (flag == "--domain") {
      domain = static_cast<uint32_t>(std::atoi(argv[i + 1]));
    } else {
      std::fputs("usage: ros2_clock_echo [--count N] [--timeout-s S] [--domain ID]\n", stderr);
      return 2;
    }
  }
  sitlnet::ros2_clock::ClockTopic clock(domain);
  const dds_entity_t reader = dds_create_reader(clock.participant, clock.topic, clock.qos, nullptr);
  sitlnet::ros2_clock::ExitIfDdsError(reader, "ros2_clock_echo", "create reader");
  const dds_entity_t waitset = dds_create_waitset(clock.participant);
  const dds_entity_t readable = dds_create_readcondition(reader, DDS_ANY_STATE);
  dds_waitset_attach(waitset, readable, reader);
  const dds_time_t deadline = dds_time() + static_cast<dds_duration_t>(timeout_s * 1e9);
  int received = 0;
  while (received < count) {
    const dds_time_t now = dds_time();
    if (now >= deadline) break;
    dds_waitset_wait(waitset, nullptr, 0, deadline - now);
    rosgraph_msgs_msg_dds__Clock_ message{};
    void* samples[1] = {&message};
    dds_sample_info_t info[1];
    while (received < count && dds_take(reader, samples, info, 1, 1) > 0) {
      if (!info[0].valid_data) continue;
      std::printf("clock %d.%09u\n", message.clock.sec, message.clock.nanosec);
      ++received;
    }
    std::fflush(stdout);
  }
  if (received < count) {
    std::fprintf(stderr, "ros2_clock_echo: %d of %d /clock messages in %g s\n", received, count,
                 timeout_s);
    return 1;
  }
  return 0;
}

// ros2_clock_publisher: puts the run's virtual time on ROS 2's /clock inside one robot.
// Started by `sitlnet run` in each robot (Timing.ros2_clock_hz > 0), sandboxed like an image;
// reads the time from the memfd it inherits (SharedVirtualTime) and publishes
// rosgraph_msgs/msg/Clock each time virtual time passes a multiple of 1/rate. docs/time.md.
#include <signal.h>
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "ros2_clock/dds.h"
#include "ros2_clock/ros2_clock.h"

namespace {

volatile sig_atomic_t g_stop = 0;

constexpr const char* kUsage =
    "usage: ros2_clock_publisher --time-fd FD --rate-hz HZ [--poll-us US] [--domain ID]\n";

}  // namespace

int main(int argc, char** argv) {
  using sitlnet::TimeNs;
  int time_fd = -1;
  double rate_hz = 0;
  long poll_us = 1000;
  uint32_t domain = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--time-fd") {
      time_fd = std::atoi(argv[i + 1]);
    } else if (flag == "--rate-hz") {
      rate_hz = std::atof(argv[i + 1]);
    } else if (flag == "--poll-us") {
      poll_us = std::atol(argv[i + 1]);
    } else if (flag == "--domain") {
      domain = static_cast<uint32_t>(std::atoi(argv[i + 1]));
    } else {
      std::fputs(kUsage, stderr);
      return 2;
    }
  }
  if (time_fd < 0 || !(rate_hz > 0 && rate_hz <= 1e6) || poll_us < 1 || poll_us > 1000000) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  signal(SIGTERM, [](int) { g_stop = 1; });
  signal(SIGINT, [](int) { g_stop = 1; });
  try {
    const sitlnet::ros2_clock::SharedVirtualTime shared =
        sitlnet::ros2_clock::SharedVirtualTime::Open(time_fd);
    sitlnet::ros2_clock::ClockTopic clock(domain);
    const dds_entity_t writer =
        dds_create_writer(clock.participant, clock.topic, clock.qos, nullptr);
    sitlnet::ros2_clock::ExitIfDdsError(writer, "ros2_clock_publisher", "create writer");
    const auto period_ns = static_cast<TimeNs>(1e9 / rate_hz);
    TimeNs next_ns = 0;
    std::printf("ros2_clock_publisher: /clock at %g Hz of virtual time\n", rate_hz);
    std::fflush(stdout);
    const timespec poll{0, poll_us * 1000};
    while (!g_stop) {
      const TimeNs now_ns = shared.Load();
      if (now_ns >= next_ns) {
        rosgraph_msgs_msg_dds__Clock_ message{};
        message.clock.sec = static_cast<int32_t>(now_ns / 1000000000);
        message.clock.nanosec = static_cast<uint32_t>(now_ns % 1000000000);
        sitlnet::ros2_clock::ExitIfDdsError(dds_write(writer, &message), "ros2_clock_publisher",
                                            "write /clock");
        next_ns = (now_ns / period_ns + 1) * period_ns;
      }
      nanosleep(&poll, nullptr);
    }
  } catch (const sitlnet::Error& error) {
    std::fprintf(stderr, "ros2_clock_publisher: %s\n", error.what());
    return 1;
  }
  return 0;
}

// sitlnet ros2_clock: the simulation's time on ROS 2's /clock topic inside every robot
// (docs/time.md, "ROS 2 /clock"). A run shares its virtual time with one publisher process per
// robot through SharedVirtualTime; the publisher puts it on DDS with Cyclone DDS, on the robot's
// loopback only.
#ifndef SITLNET_ROS2_CLOCK_ROS2_CLOCK_H_
#define SITLNET_ROS2_CLOCK_ROS2_CLOCK_H_

#include <atomic>
#include <string>

#include "common/common.h"

namespace sitlnet::ros2_clock {

// ROS 2's names on DDS for /clock (rmw_cyclonedds: topic prefix "rt", type names
// "<package>::msg::dds_::<Message>_"); docs/references.md#ros2-clock.
inline constexpr const char* kTopicName = "rt/clock";
inline constexpr const char* kTypeName = "rosgraph_msgs::msg::dds_::Clock_";

// The run's current virtual time in a page of shared memory (a memfd): the run stores it every
// iteration, the publishers read it. One 64-bit atomic, lock-free, so neither side waits.
class SharedVirtualTime {
 public:
  // Creates the memfd (close-on-exec; handed to a publisher by number, see robot_images).
  static SharedVirtualTime Create();
  // Maps an inherited memfd read-only (the publisher). Throws Error naming the fd.
  static SharedVirtualTime Open(int fd);
  SharedVirtualTime(SharedVirtualTime&& other) noexcept;
  SharedVirtualTime& operator=(SharedVirtualTime&&) = delete;
  SharedVirtualTime(const SharedVirtualTime&) = delete;
  ~SharedVirtualTime();

  int fd() const { return fd_; }
  void Store(TimeNs virtual_ns) { value_->store(virtual_ns, std::memory_order_release); }
  TimeNs Load() const { return value_->load(std::memory_order_acquire); }

 private:
  SharedVirtualTime(int fd, std::atomic<TimeNs>* value, bool owns_fd);
  int fd_ = -1;
  std::atomic<TimeNs>* value_ = nullptr;
  bool owns_fd_ = false;
};

// Cyclone DDS configuration that keeps a participant on the loopback interface only, with
// unicast discovery (loopback has no multicast): nothing of /clock goes over the robot's radio.
// ROS 2 nodes in the robot use the same (docs/time.md gives it as CYCLONEDDS_URI).
std::string LoopbackOnlyCycloneConfig();

}  // namespace sitlnet::ros2_clock

#endif  // SITLNET_ROS2_CLOCK_ROS2_CLOCK_H_

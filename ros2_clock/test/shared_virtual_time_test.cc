#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "ros2_clock/ros2_clock.h"

namespace sitlnet::ros2_clock {
namespace {

// What the run stores is what a publisher, another process holding only the descriptor, reads.
TEST(SharedVirtualTimeTest, AnotherProcessReadsWhatTheRunStores) {
  SharedVirtualTime shared = SharedVirtualTime::Create();
  EXPECT_EQ(shared.Load(), 0);
  shared.Store(1234567890123);
  int to_child[2];
  ASSERT_EQ(pipe(to_child), 0);
  const pid_t child = fork();
  if (child == 0) {
    char go = 0;
    if (read(to_child[0], &go, 1) != 1) _exit(3);
    const SharedVirtualTime seen = SharedVirtualTime::Open(shared.fd());
    _exit(seen.Load() == 42 * kNsPerS ? 0 : 1);
  }
  shared.Store(42 * kNsPerS);  // After the fork: the child sees it through the memfd.
  ASSERT_EQ(write(to_child[1], "g", 1), 1);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  close(to_child[0]);
  close(to_child[1]);
}

TEST(SharedVirtualTimeTest, LoopbackOnlyConfigNamesLoopbackAndNoMulticast) {
  const std::string config = LoopbackOnlyCycloneConfig();
  EXPECT_NE(config.find("<NetworkInterface name=\"lo\"/>"), std::string::npos);
  EXPECT_NE(config.find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
  EXPECT_NE(config.find("<Peer address=\"127.0.0.1\"/>"), std::string::npos);
}

}  // namespace
}  // namespace sitlnet::ros2_clock

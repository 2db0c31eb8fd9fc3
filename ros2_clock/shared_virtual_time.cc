// SharedVirtualTime: one atomic in a memfd page.
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>

#include "ros2_clock/ros2_clock.h"

namespace sitlnet::ros2_clock {
namespace {

static_assert(std::atomic<TimeNs>::is_always_lock_free, "shared across processes");

std::atomic<TimeNs>* Map(int fd, int protection, const char* what) {
  void* page = mmap(nullptr, sizeof(std::atomic<TimeNs>), protection, MAP_SHARED, fd, 0);
  if (page == MAP_FAILED) throw Error(SystemErrorMessage(what, errno));
  return static_cast<std::atomic<TimeNs>*>(page);
}

}  // namespace

SharedVirtualTime::SharedVirtualTime(int fd, std::atomic<TimeNs>* value, bool owns_fd)
    : fd_(fd), value_(value), owns_fd_(owns_fd) {}

SharedVirtualTime::SharedVirtualTime(SharedVirtualTime&& other) noexcept
    : fd_(other.fd_), value_(other.value_), owns_fd_(other.owns_fd_) {
  other.fd_ = -1;
  other.value_ = nullptr;
  other.owns_fd_ = false;
}

SharedVirtualTime SharedVirtualTime::Create() {
  const int fd = memfd_create("sitlnet-virtual-time", MFD_CLOEXEC);
  if (fd < 0) throw Error(SystemErrorMessage("create the shared virtual time", errno));
  if (ftruncate(fd, sizeof(std::atomic<TimeNs>)) != 0) {
    const int err = errno;
    close(fd);
    throw Error(SystemErrorMessage("size the shared virtual time", err));
  }
  SharedVirtualTime shared(fd, Map(fd, PROT_READ | PROT_WRITE, "map the shared virtual time"),
                           true);
  shared.Store(0);
  return shared;
}

SharedVirtualTime SharedVirtualTime::Open(int fd) {
  return SharedVirtualTime(
      fd, Map(fd, PROT_READ, ("map the shared virtual time, fd " + std::to_string(fd)).c_str()),
      false);
}

SharedVirtualTime::~SharedVirtualTime() {
  if (value_ != nullptr) munmap(value_, sizeof(std::atomic<TimeNs>));
  if (owns_fd_ && fd_ >= 0) close(fd_);
}

std::string LoopbackOnlyCycloneConfig() {
  return "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
         "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><Peers>"
         "<Peer address=\"127.0.0.1\"/></Peers><ParticipantIndex>auto</ParticipantIndex>"
         "<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex></Discovery></Domain>"
         "</CycloneDDS>";
}

}  // namespace sitlnet::ros2_clock

// Network sysctls of the calling thread's namespace, also where /proc/sys is mounted read-only
// (a container: podman and Docker bind it read-only over the container's /proc).
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <string_view>

#include "nns/nns_internal.h"

namespace sitlnet::nns::internal {
namespace {

// 0, or the errno of the open or write.
int WriteFile(const char* path, std::string_view value) {
  const int fd = open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  const bool written = write(fd, value.data(), value.size()) == static_cast<ssize_t>(value.size());
  const int err = written ? 0 : errno;
  close(fd);
  return err;
}

}  // namespace

int WriteNetSysctl(const std::string& path, std::string_view value) {
  const int err = WriteFile(path.c_str(), value);
  if (err != EROFS) return err;
  // A child of this thread shares its network namespace (the file's values are that
  // namespace's) and, in a mount namespace of its own, makes its copy of the /proc/sys bind
  // mount writable: CAP_SYS_ADMIN, which `up` holds anyway. Nothing changes outside the child;
  // only syscalls between fork and _exit (this process has threads).
  const pid_t child = fork();
  if (child < 0) return err;
  if (child == 0) {
    if (unshare(CLONE_NEWNS) != 0 ||
        mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        mount(nullptr, "/proc/sys", nullptr, MS_REMOUNT | MS_BIND, nullptr) != 0) {
      _exit(EROFS);
    }
    _exit(WriteFile(path.c_str(), value));
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return err;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : err;
}

}  // namespace sitlnet::nns::internal

// Named network namespaces, the iproute2 way (ip/ipnetns.c: netns_add,
// netns_delete), and per-thread entry with setns.
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <mutex>

#include "nns/nns_internal.h"

namespace sitlnet::nns {

std::string NetnsPath(const std::string& name) { return std::string(kNetnsDir) + "/" + name; }

bool NetnsExists(const std::string& name) {
  struct stat st {};
  return lstat(NetnsPath(name).c_str(), &st) == 0;
}

namespace internal {

void PrepareNetnsDir() {
  // Once per process: ip netns does the same dance on every call. The
  // directory must be a shared mount so that the bind mounts we add
  // propagate to every mount namespace (ip netns exec creates new ones).
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
    if (mkdir(kNetnsDir, 0755) != 0 && errno != EEXIST) {
      failure = SystemErrorMessage(std::string("create ") + kNetnsDir, errno);
      return;
    }
    if (mount("", kNetnsDir, "none", MS_SHARED | MS_REC, nullptr) == 0) return;
    if (errno != EINVAL) {
      failure = SystemErrorMessage(std::string("make ") + kNetnsDir + " a shared mount", errno);
      return;
    }
    // Not a mount point yet: bind it onto itself, then make it shared.
    if (mount(kNetnsDir, kNetnsDir, "none", MS_BIND | MS_REC, nullptr) != 0 ||
        mount("", kNetnsDir, "none", MS_SHARED | MS_REC, nullptr) != 0) {
      failure = SystemErrorMessage(std::string("make ") + kNetnsDir + " a shared mount", errno);
    }
  });
  // Docker's default AppArmor profile denies mount even with CAP_SYS_ADMIN.
  if (!failure.empty()) {
    throw Error(failure + " (in a container: --security-opt apparmor=unconfined)");
  }
}

void CreateNetnsAndEnter(const std::string& name) {
  PrepareNetnsDir();
  const std::string path = NetnsPath(name);
  const int file = open(path.c_str(), O_RDONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0);
  if (file < 0) throw Error(SystemErrorMessage("create namespace file \"" + path + "\"", errno));
  close(file);
  if (unshare(CLONE_NEWNET) != 0) {
    const int err = errno;
    unlink(path.c_str());
    throw Error(SystemErrorMessage("unshare network namespace for \"" + name + "\"", err));
  }
  // thread-self, not self: only this thread moved (docs/references.md#linux).
  if (mount("/proc/thread-self/ns/net", path.c_str(), "none", MS_BIND, nullptr) != 0) {
    const int err = errno;
    unlink(path.c_str());
    throw Error(SystemErrorMessage("bind-mount namespace onto \"" + path + "\"", err));
  }
}

bool AllowUnprivilegedPing() {
  // /proc/sys/net follows the calling thread's namespace (current->nsproxy), so this writes the
  // robot's copy; the root namespace keeps its own value. Needs no capability beyond being the
  // file's owner (uid 0): gids are checked against this process's user namespace.
  return WriteNetSysctl("/proc/sys/net/ipv4/ping_group_range", "0 2147483647") == 0;
}

bool StatNs(const std::string& path, NsId* id) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return false;
  id->dev = st.st_dev;
  id->ino = st.st_ino;
  return true;
}

}  // namespace internal

std::string CtlNetnsName(const std::string& scenario) { return scenario + ".ctl"; }

std::function<void(const std::function<void()>&)> InNetns(const std::string& name) {
  return [name](const std::function<void()>& work) {
    ScopedNetns inside(name);
    work();
  };
}

void CreateNetns(const std::string& name) {
  ScopedNetns restore(UniqueFd(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC)).get());
  internal::CreateNetnsAndEnter(name);
}

bool RemoveNetns(const std::string& name) {
  const std::string path = NetnsPath(name);
  // MNT_DETACH as ip netns del: a process with its cwd there must not block us.
  umount2(path.c_str(), MNT_DETACH);
  if (unlink(path.c_str()) != 0) {
    if (errno == ENOENT) return false;
    throw Error(SystemErrorMessage("remove namespace file \"" + path + "\"", errno));
  }
  return true;
}

UniqueFd OpenNetns(const std::string& name) {
  UniqueFd fd(open(NetnsPath(name).c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd.valid()) throw Error(SystemErrorMessage("open namespace \"" + name + "\"", errno));
  return fd;
}

ScopedNetns::ScopedNetns(const std::string& name) {
  UniqueFd target = OpenNetns(name);
  Enter(target.get(), "namespace \"" + name + "\"");
}

ScopedNetns::ScopedNetns(int netns_fd) { Enter(netns_fd, "namespace fd"); }

void ScopedNetns::Enter(int netns_fd, const std::string& what) {
  original_.Reset(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC));
  if (!original_.valid()) throw Error(SystemErrorMessage("open own network namespace", errno));
  if (setns(netns_fd, CLONE_NEWNET) != 0) {
    const int err = errno;
    original_.Reset();
    throw Error(SystemErrorMessage("enter " + what, err));
  }
}

ScopedNetns::~ScopedNetns() {
  if (!original_.valid()) return;
  // A thread left in a robot's namespace would silently open sockets there:
  // treat failure to return as a bug.
  SITLNET_DEMAND(setns(original_.get(), CLONE_NEWNET) == 0);
}

}  // namespace sitlnet::nns

#include "tapbridge/tap_port.h"

#include <fcntl.h>
#include <linux/if.h>
#include <linux/if_tun.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "common/common.h"

namespace sitlnet::tapbridge {
namespace {

// Returns the calling thread to its original namespace on scope exit; a
// failure to return is a bug-level condition (the thread would keep working
// in a robot's namespace), so it aborts.
class ThreadNetnsGuard {
 public:
  ThreadNetnsGuard() : original_(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC)) {}
  ~ThreadNetnsGuard() {
    if (entered_) SITLNET_DEMAND(setns(original_, CLONE_NEWNET) == 0);
    if (original_ >= 0) close(original_);
  }
  bool ok() const { return original_ >= 0; }
  void MarkEntered() { entered_ = true; }

 private:
  int original_;
  bool entered_ = false;
};

}  // namespace

TapPort::TapPort(const std::string& netns, const std::string& ifname)
    : netns_(netns), ifname_(ifname) {
  const std::string what = "attach TAP " + ifname + " in netns " + netns;
  const std::string path = "/run/netns/" + netns;
  const int ns_fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (ns_fd < 0) throw Error(SystemErrorMessage(what + ": open " + path, errno));
  struct stat ns_stat {};
  fstat(ns_fd, &ns_stat);
  netns_inode_ = ns_stat.st_ino;
  {
    ThreadNetnsGuard guard;
    if (!guard.ok()) {
      close(ns_fd);
      throw Error(SystemErrorMessage(what + ": open own namespace", errno));
    }
    if (setns(ns_fd, CLONE_NEWNET) != 0) {
      const int err = errno;
      close(ns_fd);
      throw Error(SystemErrorMessage(what + ": setns", err));
    }
    guard.MarkEntered();
    close(ns_fd);
    fd_ = open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) throw Error(SystemErrorMessage(what + ": open /dev/net/tun", errno));
    ifreq request{};
    // Same flags as nns creates the persistent device with; offloads and
    // IFF_VNET_HDR stay off so frames are 802.11-sized (reference.md).
    request.ifr_flags = IFF_TAP | IFF_NO_PI;
    std::snprintf(request.ifr_name, IFNAMSIZ, "%s", ifname.c_str());
    if (ioctl(fd_, TUNSETIFF, &request) != 0) {
      const int err = errno;
      close(fd_);
      fd_ = -1;
      throw Error(SystemErrorMessage(what + ": TUNSETIFF", err));
    }
    // seq_open_net binds the file to the opener's namespace: later reads from
    // the root namespace still show the robot's devices.
    proc_net_dev_fd_ = open("/proc/thread-self/net/dev", O_RDONLY | O_CLOEXEC);
  }
}

TapPort::~TapPort() {
  if (fd_ >= 0) close(fd_);
  if (proc_net_dev_fd_ >= 0) close(proc_net_dev_fd_);
}

ssize_t TapPort::Read(std::span<uint8_t> buffer) {
  const ssize_t n = read(fd_, buffer.data(), buffer.size());
  if (n >= 0) return n;
  if (errno == EAGAIN || errno == EWOULDBLOCK) return 0;
  return -errno;
}

int TapPort::Write(std::span<const uint8_t> frame) {
  const ssize_t n = write(fd_, frame.data(), frame.size());
  if (n == static_cast<ssize_t>(frame.size())) return 0;
  return n < 0 ? -errno : -EIO;
}

std::optional<uint64_t> TapPort::KernelTxDropped() {
  if (proc_net_dev_fd_ < 0) return std::nullopt;
  char text[16384];
  const ssize_t n = pread(proc_net_dev_fd_, text, sizeof text - 1, 0);
  if (n <= 0) return std::nullopt;
  text[n] = '\0';
  std::istringstream lines(text);
  std::string line;
  const std::string key = ifname_ + ":";
  while (std::getline(lines, line)) {
    const size_t at = line.find(key);
    if (at == std::string::npos) continue;
    // "wlan0: rx_bytes rx_packets rx_errs rx_drop rx_fifo rx_frame rx_compressed
    //  rx_multicast tx_bytes tx_packets tx_errs tx_drop ..." (net/core/net-procfs.c)
    std::istringstream fields(line.substr(at + key.size()));
    uint64_t value = 0;
    for (int i = 0; i < 12 && (fields >> value); ++i) {
      if (i == 11) return value;
    }
  }
  return std::nullopt;
}

}  // namespace sitlnet::tapbridge

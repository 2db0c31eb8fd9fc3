#include "tapbridge/tap_port.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <sstream>

#include "common/common.h"
#include "nns/nns.h"

namespace sitlnet::tapbridge {

TapPort::TapPort(const std::string& netns, const std::string& ifname)
    : netns_(netns), ifname_(ifname) {
  // nns owns attaching: it refuses a missing device instead of letting TUNSETIFF create a
  // fresh, non-persistent one that nobody configured.
  UniqueFd tap = nns::AttachTap(netns, ifname, /*nonblocking=*/true);
  const std::string path = "/run/netns/" + netns;
  struct stat ns_stat {};
  if (stat(path.c_str(), &ns_stat) != 0) {
    throw Error(SystemErrorMessage(
        "attach to TAP \"" + ifname + "\" in namespace \"" + netns + "\": stat " + path, errno));
  }
  netns_inode_ = ns_stat.st_ino;
  {
    // seq_open_net binds the file to the opener's namespace: later reads from the root
    // namespace still show the robot's devices.
    nns::ScopedNetns inside(netns);
    proc_net_dev_fd_.Reset(open("/proc/thread-self/net/dev", O_RDONLY | O_CLOEXEC));
  }
  fd_ = std::move(tap);
}

ssize_t TapPort::Read(std::span<uint8_t> buffer) {
  const ssize_t n = read(fd_.get(), buffer.data(), buffer.size());
  if (n >= 0) return n;
  if (errno == EAGAIN || errno == EWOULDBLOCK) return 0;
  return -errno;
}

int TapPort::Write(std::span<const uint8_t> frame) {
  const ssize_t n = write(fd_.get(), frame.data(), frame.size());
  if (n == static_cast<ssize_t>(frame.size())) return 0;
  return n < 0 ? -errno : -EIO;
}

std::optional<uint64_t> TapPort::KernelTxDropped() {
  if (!proc_net_dev_fd_.valid()) return std::nullopt;
  char text[16384];
  const ssize_t n = pread(proc_net_dev_fd_.get(), text, sizeof text - 1, 0);
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

// TAP devices: created inside a robot's namespace (so they are born there),
// persistent so that the medium daemon can attach and re-attach.
#include <fcntl.h>
#include <linux/if.h>
#include <linux/if_tun.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "nns/nns_internal.h"

namespace sitlnet::nns {
namespace {

// Opens /dev/net/tun and binds it to TAP `ifname` in the calling thread's
// namespace (creating it if absent). IFF_NO_PI: frames are bare Ethernet.
// No IFF_VNET_HDR: offloads would yield 64 KB superframes (docs/references.md#linux).
UniqueFd OpenTap(const std::string& ifname, int open_flags, const std::string& what) {
  UniqueFd fd(open("/dev/net/tun", O_RDWR | O_CLOEXEC | open_flags));
  if (!fd.valid()) throw Error(SystemErrorMessage(what + ": open /dev/net/tun", errno));
  ifreq ifr{};
  ifr.ifr_flags = IFF_TAP | IFF_NO_PI;
  std::strncpy(ifr.ifr_name, ifname.c_str(), IFNAMSIZ - 1);
  if (ioctl(fd.get(), TUNSETIFF, &ifr) != 0) {
    throw Error(SystemErrorMessage(what + ": TUNSETIFF", errno));
  }
  return fd;
}

}  // namespace

namespace internal {

void CreatePersistentTap(const std::string& ifname, const std::string& what) {
  // Called only in a namespace created a moment ago: no TAP of that name can
  // exist there, so TUNSETIFF creates rather than attaches.
  UniqueFd fd = OpenTap(ifname, 0, what);
  if (ioctl(fd.get(), TUNSETPERSIST, 1) != 0) {
    throw Error(SystemErrorMessage(what + ": TUNSETPERSIST", errno));
  }
}

}  // namespace internal

UniqueFd AttachTap(const std::string& netns, const std::string& ifname, bool nonblocking) {
  const std::string what = "attach to TAP \"" + ifname + "\" in namespace \"" + netns + "\"";
  ScopedNetns inside(netns);
  // Without IFF_TAP|IFF_NO_PI matching the device, TUNSETIFF fails with EINVAL;
  // an absent device would be created: check first (we are in its namespace).
  internal::RouteSocket sock;
  if (internal::LinkIndex(sock, ifname) == 0) throw Error(what + ": no such device");
  return OpenTap(ifname, nonblocking ? O_NONBLOCK : 0, what);
}

}  // namespace sitlnet::nns

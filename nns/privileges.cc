// Privilege check: one line naming what is missing and how to get it.
#include <fcntl.h>
#include <linux/capability.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "nns/nns_internal.h"

namespace sitlnet::nns {

std::optional<std::string> MissingPrivileges() {
  std::string missing;
  auto add = [&missing](const std::string& item) {
    missing.append(missing.empty() ? "" : ", ").append(item);
  };
  // TAP/veth creation and addresses need CAP_NET_ADMIN; unshare, setns and
  // the /run/netns mounts need CAP_SYS_ADMIN (docs/references.md#linux).
  if (!HasEffectiveCapability(CAP_NET_ADMIN)) add("CAP_NET_ADMIN");
  if (!HasEffectiveCapability(CAP_SYS_ADMIN)) add("CAP_SYS_ADMIN");
  const int tun = open("/dev/net/tun", O_RDWR | O_CLOEXEC);
  if (tun >= 0) {
    close(tun);
  } else {
    add("read-write /dev/net/tun (" + std::string(std::strerror(errno)) + ")");
  }
  if (missing.empty()) return std::nullopt;
  return "missing " + missing +
         ": run as root (sudo), or in docker add --cap-add NET_ADMIN --cap-add SYS_ADMIN "
         "--device /dev/net/tun --security-opt apparmor=unconfined";
}

void RequirePrivileges() {
  if (auto missing = MissingPrivileges()) throw PrivilegeError(*missing);
}

}  // namespace sitlnet::nns

// A robot's persistent wlan0 TAP, attached from the root namespace.
#ifndef SITLNET_TAPBRIDGE_TAP_PORT_H_
#define SITLNET_TAPBRIDGE_TAP_PORT_H_

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

// The default Port of a robot. Owns the TAP fd (non-blocking) and an fd of the namespace's
// /proc/net/dev (opened inside the namespace, so reads keep showing that namespace).
class TapPort : public Port {
 public:
  // Attaches to the existing TAP `ifname` in /run/netns/<netns> through
  // nns::AttachTap. Throws Error 'attach to TAP "<ifname>" in namespace "<netns>": <why>',
  // also when the device does not exist ("no such device": it is never created here).
  TapPort(const std::string& netns, const std::string& ifname);
  TapPort(const TapPort&) = delete;
  TapPort& operator=(const TapPort&) = delete;

  int fd() const override { return fd_.get(); }
  const std::string& netns() const { return netns_; }
  // Inode of the namespace attached to (to notice a namespace replaced).
  ino_t netns_inode() const { return netns_inode_; }

  // One frame into `buffer`; its length, 0 when drained (EAGAIN), -errno on error.
  ssize_t Read(std::span<uint8_t> buffer) override;
  // One frame out; 0 or -errno.
  int Write(std::span<const uint8_t> frame) override;
  // tx_dropped of the TAP as the kernel counts it (frames the kernel could not
  // queue for us to read: the TAP overflowed). nullopt if unreadable.
  std::optional<uint64_t> KernelTxDropped() override;

 private:
  std::string netns_;
  std::string ifname_;
  UniqueFd fd_;
  UniqueFd proc_net_dev_fd_;
  ino_t netns_inode_ = 0;
};

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_TAP_PORT_H_

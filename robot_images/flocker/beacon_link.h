// The flocker's radio link: UDP broadcast of FlockerBeacon on wlan0 only.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_LINK_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_LINK_H_

#include <cstdint>
#include <string>
#include <vector>

#include "sitlnet/flocker.pb.h"

namespace sitlnet::flocker {

class BeaconLink {
 public:
  // Binds UDP `port` on `device` (SO_BINDTODEVICE), broadcast enabled, its datagrams carrying
  // IPv4 TOS byte `tos` (0-255). Throws std::runtime_error naming the device on failure.
  BeaconLink(const std::string& device, uint16_t port, int tos = 0);
  ~BeaconLink();
  BeaconLink(const BeaconLink&) = delete;
  BeaconLink& operator=(const BeaconLink&) = delete;

  // Broadcasts to 255.255.255.255:port out of the bound device.
  bool Send(const proto::FlockerBeacon& beacon);

  // Reads every queued datagram without blocking; malformed ones are counted.
  std::vector<proto::FlockerBeacon> Drain();
  uint64_t malformed() const { return malformed_; }

 private:
  int fd_ = -1;
  uint16_t port_;
  uint64_t malformed_ = 0;
};

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_LINK_H_

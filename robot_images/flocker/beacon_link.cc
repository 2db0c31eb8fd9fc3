#include "robot_images/flocker/beacon_link.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sitlnet::flocker {

BeaconLink::BeaconLink(const std::string& device, uint16_t port, int tos) : port_(port) {
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("beacon socket: ") + std::strerror(errno));
  const int one = 1;
  // Path-MTU discovery "do": the kernel then sets DF and IP ID 0 on these
  // unconnected datagrams instead of a randomly keyed ID, so that lockstep
  // runs give byte-identical captures (beacons are far below any MTU).
  const int pmtu_do = IP_PMTUDISC_DO;
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_port = htons(port);
  if (setsockopt(fd_, SOL_SOCKET, SO_BINDTODEVICE, device.c_str(), device.size()) != 0 ||
      setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) != 0 ||
      setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
      setsockopt(fd_, IPPROTO_IP, IP_MTU_DISCOVER, &pmtu_do, sizeof pmtu_do) != 0 ||
      setsockopt(fd_, IPPROTO_IP, IP_TOS, &tos, sizeof tos) != 0 ||
      bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
    const std::string message = "beacon socket on " + device + " port " + std::to_string(port) +
                                ": " + std::strerror(errno);
    close(fd_);
    throw std::runtime_error(message);
  }
}

BeaconLink::~BeaconLink() {
  if (fd_ >= 0) close(fd_);
}

bool BeaconLink::Send(const proto::FlockerBeacon& beacon) {
  const std::string bytes = beacon.SerializeAsString();
  sockaddr_in all{};
  all.sin_family = AF_INET;
  all.sin_port = htons(port_);
  all.sin_addr.s_addr = htonl(INADDR_BROADCAST);
  return sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&all),
                sizeof all) == static_cast<ssize_t>(bytes.size());
}

std::vector<proto::FlockerBeacon> BeaconLink::Drain() {
  std::vector<proto::FlockerBeacon> beacons;
  char buffer[2048];
  for (;;) {
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    if (n < 0) break;  // EAGAIN: drained
    proto::FlockerBeacon beacon;
    if (beacon.ParseFromArray(buffer, static_cast<int>(n)) && beacon.has_robot()) {
      beacons.push_back(std::move(beacon));
    } else {
      ++malformed_;
    }
  }
  return beacons;
}

}  // namespace sitlnet::flocker

// A non-blocking IPv4 UDP socket (RAII).
#ifndef SITLNET_PHYSICS_MUJOCO_UDP_SOCKET_H_
#define SITLNET_PHYSICS_MUJOCO_UDP_SOCKET_H_

#include <netinet/in.h>
#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/common.h"

namespace sitlnet::physics {

sockaddr_in MakeSockaddr(Ipv4 address, uint16_t port);
Ipv4 SockaddrIpv4(const sockaddr_in& address);

// Where UdpSocket::ReceiveBatch puts one datagram: `data` (`capacity` bytes, the caller's) and,
// filled in, its full length (> capacity: it was truncated) and its sender.
struct DatagramSlot {
  uint8_t* data = nullptr;
  size_t capacity = 0;
  ssize_t length = 0;
  sockaddr_in from{};
};

class UdpSocket {
 public:
  UdpSocket() = default;
  // Binds address:port, non-blocking. With `freebind` (IP_FREEBIND) the address need not
  // exist yet. Throws Error "<what>: bind a.b.c.d:port: <strerror>".
  static UdpSocket Bind(Ipv4 address, uint16_t port, bool freebind, const std::string& what);
  ~UdpSocket();
  UdpSocket(UdpSocket&& other) noexcept;
  UdpSocket& operator=(UdpSocket&& other) noexcept;

  int fd() const { return fd_; }

  // One datagram into `buffer`. Returns its full length (> capacity means it was truncated),
  // or -1 when nothing is waiting.
  ssize_t Receive(void* buffer, size_t capacity, sockaddr_in* from) const;
  // Up to `count` waiting datagrams in one system call (recvmmsg), one per slot. Returns how
  // many came (0 when nothing is waiting); the first that many slots have length and from set.
  int ReceiveBatch(DatagramSlot* slots, int count) const;
  // Returns false (errno kept) if the kernel refused the datagram.
  bool SendTo(const void* data, size_t size, const sockaddr_in& to) const;

 private:
  explicit UdpSocket(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_UDP_SOCKET_H_

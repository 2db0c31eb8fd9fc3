#include "physics_mujoco/udp_socket.h"

#include <arpa/inet.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <utility>

namespace sitlnet::physics {

sockaddr_in MakeSockaddr(Ipv4 address, uint16_t port) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(port);
  sa.sin_addr.s_addr = htonl(address.host_order);
  return sa;
}

Ipv4 SockaddrIpv4(const sockaddr_in& address) { return Ipv4{ntohl(address.sin_addr.s_addr)}; }

UdpSocket UdpSocket::Bind(Ipv4 address, uint16_t port, bool freebind, const std::string& what) {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw Error(SystemErrorMessage(what + ": create UDP socket", errno));
  UdpSocket sock(fd);
  const int one = 1;
  if (freebind && setsockopt(fd, IPPROTO_IP, IP_FREEBIND, &one, sizeof one) != 0) {
    throw Error(SystemErrorMessage(what + ": set IP_FREEBIND", errno));
  }
  const sockaddr_in sa = MakeSockaddr(address, port);
  if (bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
    const int err = errno;
    const std::string endpoint = FormatIpv4(address) + ":" + std::to_string(port);
    // Any local user can hold the port first (IP_FREEBIND needs no privilege): say how to find
    // the holder (docs/security.md, finding 10).
    const std::string hint =
        err == EADDRINUSE
            ? " (another process holds it: ss -uanp 'sport = :" + std::to_string(port) + "')"
            : "";
    throw Error(SystemErrorMessage(what + ": bind UDP " + endpoint, err) + hint);
  }
  return sock;
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) close(fd_);
}

UdpSocket::UdpSocket(UdpSocket&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

ssize_t UdpSocket::Receive(void* buffer, size_t capacity, sockaddr_in* from) const {
  socklen_t length = sizeof *from;
  // MSG_TRUNC: the return value is the datagram's real length, so oversize is detectable.
  const ssize_t n =
      recvfrom(fd_, buffer, capacity, MSG_TRUNC, reinterpret_cast<sockaddr*>(from), &length);
  return n < 0 ? -1 : n;
}

int UdpSocket::ReceiveBatch(DatagramSlot* slots, int count) const {
  constexpr int kMaxBatch = 64;
  count = std::min(count, kMaxBatch);
  mmsghdr messages[kMaxBatch];
  iovec vectors[kMaxBatch];
  for (int i = 0; i < count; ++i) {
    vectors[i] = {slots[i].data, slots[i].capacity};
    messages[i] = {};
    messages[i].msg_hdr.msg_name = &slots[i].from;
    messages[i].msg_hdr.msg_namelen = sizeof slots[i].from;
    messages[i].msg_hdr.msg_iov = &vectors[i];
    messages[i].msg_hdr.msg_iovlen = 1;
  }
  // MSG_TRUNC: each msg_len is the datagram's real length, so oversize is detectable. Non-blocking
  // socket: returns what is waiting, up to count, without waiting for more.
  const int n = recvmmsg(fd_, messages, static_cast<unsigned>(count), MSG_TRUNC, nullptr);
  if (n <= 0) return 0;
  for (int i = 0; i < n; ++i) {
    slots[i].length = static_cast<ssize_t>(messages[i].msg_len);
    // A kernel that reports the truncated length instead: still more than the buffer.
    if ((messages[i].msg_hdr.msg_flags & MSG_TRUNC) != 0 &&
        slots[i].length <= static_cast<ssize_t>(slots[i].capacity)) {
      slots[i].length = static_cast<ssize_t>(slots[i].capacity) + 1;
    }
  }
  return n;
}

bool UdpSocket::SendTo(const void* data, size_t size, const sockaddr_in& to) const {
  return sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
         static_cast<ssize_t>(size);
}

}  // namespace sitlnet::physics

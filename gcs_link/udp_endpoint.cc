// A GCS on UDP: datagrams to HOST:PORT from an unconnected socket, so that a GCS that is absent,
// starts late or restarts never ends the link; a connected socket would fail its next send after
// the ICMP "port unreachable" (what ended socat in issue 47). Answers are taken from any sender:
// a GCS may reply from another port than the one it listens on.
#include <arpa/inet.h>
#include <linux/errqueue.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cerrno>

#include "gcs_link/frame_stream.h"
#include "gcs_link/host_endpoint.h"
#include "common/common.h"

namespace sitlnet::gcs {
namespace {

constexpr int kMaxReadsPerWake = 64;  // So that a flooding GCS cannot starve the vehicles.
constexpr size_t kMaxDatagramBytes = 65536;

class UdpEndpoint final : public HostEndpoint {
 public:
  explicit UdpEndpoint(const GcsEndpoint& endpoint) : text_(endpoint.text) {
    gcs_.sin_family = AF_INET;
    gcs_.sin_port = htons(endpoint.port);
    SITLNET_DEMAND(inet_pton(AF_INET, endpoint.host.c_str(), &gcs_.sin_addr) == 1);
    socket_.Reset(socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!socket_.valid()) throw Error(SystemErrorMessage("socket for --gcs " + text_, errno));
    // ICMP errors go to the socket's error queue, where they are counted; an unconnected socket
    // hears of none without it.
    const int on = 1;
    if (setsockopt(socket_.get(), SOL_IP, IP_RECVERR, &on, sizeof on) != 0) {
      throw Error(SystemErrorMessage("IP_RECVERR for --gcs " + text_, errno));
    }
    // A loopback GCS: bound to loopback, so that only local programs can command the vehicles.
    sockaddr_in local{};
    local.sin_family = AF_INET;
    const bool loopback = (ntohl(gcs_.sin_addr.s_addr) >> 24) == 127;
    local.sin_addr.s_addr = htonl(loopback ? INADDR_LOOPBACK : INADDR_ANY);
    if (bind(socket_.get(), reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
      throw Error(SystemErrorMessage("bind a UDP port for --gcs " + text_, errno));
    }
    buffer_.resize(kMaxDatagramBytes);
  }

  void AppendPollFds(std::vector<pollfd>* fds) const override {
    fds->push_back({socket_.get(), POLLIN, 0});  // POLLERR is always reported.
  }

  bool HandleReady(const pollfd& ready, const GcsBytesSink& to_vehicles,
                   GcsRelayCounters* counters) override {
    if (ready.fd != socket_.get()) return false;
    if (ready.revents & POLLERR) DrainErrors(counters);
    for (int i = 0; i < kMaxReadsPerWake; ++i) {
      const ssize_t n = recv(socket_.get(), buffer_.data(), buffer_.size(), MSG_DONTWAIT);
      if (n < 0) {
        if (errno == ECONNREFUSED) continue;  // An ICMP error reported once; it is queued too.
        break;
      }
      ++counters->from_gcs;
      frames_.clear();
      const uint64_t dropped_before = stream_.bytes_dropped();
      const size_t taken = stream_.Push(buffer_.data(), static_cast<size_t>(n), &frames_);
      stream_.DropRest();  // A datagram holds whole frames.
      counters->from_gcs_bytes_dropped += stream_.bytes_dropped() - dropped_before;
      if (taken == 0) {
        ++counters->from_gcs_without_frame;
        continue;
      }
      to_vehicles(frames_.data(), frames_.size());
    }
    return true;
  }

  void SendToGcs(const uint8_t* data, size_t size, GcsRelayCounters* counters) override {
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (sendto(socket_.get(), data, size, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&gcs_),
                 sizeof gcs_) >= 0) {
        ++counters->to_gcs;
        return;
      }
      // ECONNREFUSED: an earlier datagram's ICMP error, reported on this call; this one was
      // not sent, so it is sent again once.
      if (errno != ECONNREFUSED) break;
    }
    ++counters->to_gcs_unreceived;
  }

 private:
  // Each queued ICMP error is a datagram the GCS's host refused.
  void DrainErrors(GcsRelayCounters* counters) {
    char control[512];
    for (int i = 0; i < kMaxReadsPerWake; ++i) {
      msghdr message{};
      message.msg_control = control;
      message.msg_controllen = sizeof control;
      if (recvmsg(socket_.get(), &message, MSG_ERRQUEUE | MSG_DONTWAIT) < 0) return;
      ++counters->to_gcs_unreceived;
    }
  }

  std::string text_;
  sockaddr_in gcs_{};
  UniqueFd socket_;
  std::vector<uint8_t> buffer_;
  FrameStream stream_;
  std::vector<uint8_t> frames_;
};

}  // namespace

std::unique_ptr<HostEndpoint> MakeUdpEndpoint(const GcsEndpoint& endpoint) {
  return std::make_unique<UdpEndpoint>(endpoint);
}

}  // namespace sitlnet::gcs

// A GCS over TCP: a server on 127.0.0.1:PORT, as ArduPilot SITL listens on 5760; MAVProxy and
// QGroundControl connect to it. Every client gets every datagram of the vehicles; what a client
// sends is cut into frames, each read's whole frames one datagram to the vehicles.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cerrno>
#include <string>

#include "gcs_link/frame_stream.h"
#include "gcs_link/host_endpoint.h"
#include "common/common.h"

namespace sitlnet::gcs {
namespace {

constexpr size_t kMaxClients = 16;
// What a slow client may owe before a datagram for it is dropped (and counted) instead.
constexpr size_t kMaxBacklogBytes = size_t{256} * 1024;
constexpr size_t kReadBytes = 4096;

struct Client {
  UniqueFd socket;
  std::string backlog;  // Bytes a full send buffer did not take, sent first.
  FrameStream stream;   // Its bytes, cut into frames (one may span reads).
};

class TcpListenEndpoint final : public HostEndpoint {
 public:
  explicit TcpListenEndpoint(const GcsEndpoint& endpoint) : text_(endpoint.text) {
    listener_.Reset(socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!listener_.valid()) throw Error(SystemErrorMessage("socket for --gcs " + text_, errno));
    const int on = 1;
    setsockopt(listener_.get(), SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(endpoint.port);
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (bind(listener_.get(), reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0 ||
        listen(listener_.get(), 4) != 0) {
      throw Error(SystemErrorMessage(
          "listen on 127.0.0.1:" + std::to_string(endpoint.port) + " for --gcs " + text_, errno));
    }
  }

  // A GCS still connected at the run's end: our side of the stream ends first, and the bytes it
  // sent that nobody read are taken, so closing is a FIN, not a reset (a close with unread
  // bytes is a reset: QGroundControl would report a lost link, not a closed one).
  ~TcpListenEndpoint() override {
    for (const Client& client : clients_) {
      shutdown(client.socket.get(), SHUT_WR);
      uint8_t buffer[kReadBytes];
      // Bounded: a GCS that floods the link cannot hold the run's end.
      for (int reads = 0; reads < 64; ++reads) {
        if (recv(client.socket.get(), buffer, sizeof buffer, MSG_DONTWAIT) <= 0) break;
      }
    }
  }

  void AppendPollFds(std::vector<pollfd>* fds) const override {
    fds->push_back({listener_.get(), POLLIN, 0});
    for (const Client& client : clients_) {
      const short events = POLLIN | (client.backlog.empty() ? 0 : POLLOUT);
      fds->push_back({client.socket.get(), events, 0});
    }
  }

  bool HandleReady(const pollfd& ready, const GcsBytesSink& to_vehicles,
                   GcsRelayCounters* counters) override {
    if (ready.fd == listener_.get()) {
      Accept(counters);
      return true;
    }
    for (size_t i = 0; i < clients_.size(); ++i) {
      Client& client = clients_[i];
      if (client.socket.get() != ready.fd) continue;
      bool open = true;
      if (ready.revents & POLLOUT) open = Flush(&client);
      if (open && (ready.revents & (POLLIN | POLLHUP | POLLERR))) {
        open = Read(client, to_vehicles, counters);
      }
      if (!open) clients_.erase(clients_.begin() + static_cast<long>(i));
      return true;
    }
    return false;
  }

  void SendToGcs(const uint8_t* data, size_t size, GcsRelayCounters* counters) override {
    if (clients_.empty()) {
      ++counters->to_gcs_unreceived;
      return;
    }
    for (Client& client : clients_) {
      if (client.backlog.size() + size > kMaxBacklogBytes) {
        ++counters->to_gcs_unreceived;
        continue;
      }
      client.backlog.append(reinterpret_cast<const char*>(data), size);
      ++counters->to_gcs;
      Flush(&client);  // A closed client is dropped at its next POLLHUP.
    }
  }

 private:
  void Accept(GcsRelayCounters* counters) {
    while (true) {
      UniqueFd accepted(
          accept4(listener_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
      if (!accepted.valid()) return;
      if (clients_.size() >= kMaxClients) continue;  // Closed at once.
      ++counters->gcs_clients;
      clients_.push_back({std::move(accepted), {}});
    }
  }

  // False once the client is gone.
  static bool Flush(Client* client) {
    while (!client->backlog.empty()) {
      const ssize_t n = send(client->socket.get(), client->backlog.data(), client->backlog.size(),
                             MSG_DONTWAIT | MSG_NOSIGNAL);
      if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
      client->backlog.erase(0, static_cast<size_t>(n));
    }
    return true;
  }

  // False once the client is gone.
  static bool Read(Client& client, const GcsBytesSink& to_vehicles, GcsRelayCounters* counters) {
    uint8_t buffer[kReadBytes];
    const ssize_t n = recv(client.socket.get(), buffer, sizeof buffer, MSG_DONTWAIT);
    if (n == 0) return false;
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    ++counters->from_gcs;
    std::vector<uint8_t> frames;
    const uint64_t dropped_before = client.stream.bytes_dropped();
    const size_t taken = client.stream.Push(buffer, static_cast<size_t>(n), &frames);
    counters->from_gcs_bytes_dropped += client.stream.bytes_dropped() - dropped_before;
    if (taken > 0) to_vehicles(frames.data(), frames.size());
    return true;
  }

  std::string text_;
  UniqueFd listener_;
  std::vector<Client> clients_;
};

}  // namespace

std::unique_ptr<HostEndpoint> MakeTcpListenEndpoint(const GcsEndpoint& endpoint) {
  return std::make_unique<TcpListenEndpoint>(endpoint);
}

}  // namespace sitlnet::gcs

#include "tapbridge/control_server.h"

#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sitlnet::tapbridge {
namespace {

constexpr size_t kMaxRequestBytes = 1 << 20;
// A pcap subscriber may lag this much before records are dropped for it.
constexpr size_t kMaxSubscriberBacklogBytes = 8 << 20;

std::string Frame(const std::string& body) {
  std::string out(4, '\0');
  const uint32_t n = static_cast<uint32_t>(body.size());
  for (int i = 0; i < 4; ++i) out[i] = static_cast<char>((n >> (8 * i)) & 0xff);
  return out + body;
}

sockaddr_un SocketAddress(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof address.sun_path) {
    throw Error("control socket path too long: " + path);
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

}  // namespace

bool ControlSocketAnswers(const std::string& path) {
  const sockaddr_un address = SocketAddress(path);
  const UniqueFd probe(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  return connect(probe.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
}

ControlServer::ControlServer(const std::string& path, EventLoop* loop, BridgeCore* core,
                             PcapFanout* fanout)
    : path_(path), loop_(loop), core_(core), fanout_(fanout) {
  const sockaddr_un address = SocketAddress(path);
  // A live daemon answers: refuse. A stale socket file (daemon killed): remove.
  if (ControlSocketAnswers(path)) throw Error("a medium daemon already serves " + path);
  unlink(path.c_str());
  listen_fd_.Reset(socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!listen_fd_.valid()) throw Error(SystemErrorMessage("socket for " + path, errno));
  if (bind(listen_fd_.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
      listen(listen_fd_.get(), 16) != 0) {
    const int err = errno;  // The member's fd is closed as the constructor throws.
    throw Error(SystemErrorMessage("listen on control socket " + path, err));
  }
  // Owner only, whatever the umask: robots share the host's filesystem, and connecting to a
  // Unix socket needs write permission on it (docs/security.md).
  if (chmod(path.c_str(), 0600) != 0) {
    const int err = errno;
    throw Error(SystemErrorMessage("chmod 0600 control socket " + path, err));
  }
  loop_->Add(listen_fd_.get(), EPOLLIN, [this](uint32_t) { Accept(); });
}

ControlServer::~ControlServer() {
  while (!connections_.empty()) Close(connections_.begin()->first);
  loop_->Remove(listen_fd_.get());
  unlink(path_.c_str());
}

void ControlServer::Accept() {
  for (;;) {
    UniqueFd accepted(accept4(listen_fd_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (!accepted.valid()) return;
    const int fd = accepted.get();
    auto connection = std::make_unique<Connection>();
    connection->fd = std::move(accepted);
    connections_[fd] = std::move(connection);
    loop_->Add(fd, EPOLLIN | EPOLLRDHUP, [this, fd](uint32_t events) { OnEvent(fd, events); });
  }
}

void ControlServer::OnEvent(int fd, uint32_t events) {
  auto it = connections_.find(fd);
  if (it == connections_.end()) return;
  Connection* c = it->second.get();
  if (events & EPOLLOUT) Flush(c);
  if (!connections_.count(fd)) return;
  if (events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR)) {
    char buffer[65536];
    for (;;) {
      const ssize_t n = read(fd, buffer, sizeof buffer);
      if (n > 0) {
        if (c->subscriber_id == 0) c->in.append(buffer, n);  // Subscribers only listen.
        continue;
      }
      if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        Close(fd);
        return;
      }
      if (errno == EAGAIN) break;
    }
    while (c->in.size() >= 4) {
      uint32_t n = 0;
      for (int i = 0; i < 4; ++i) n |= uint32_t{static_cast<uint8_t>(c->in[i])} << (8 * i);
      if (n > kMaxRequestBytes) {
        Close(fd);
        return;
      }
      if (c->in.size() < 4 + n) break;
      const std::string body = c->in.substr(4, n);
      c->in.erase(0, 4 + n);
      HandleRequest(c, body);
    }
    Flush(c);
  }
}

void ControlServer::HandleRequest(Connection* c, const std::string& bytes) {
  proto::MediumRequest request;
  proto::MediumResponse response;
  if (!request.ParseFromString(bytes)) {
    response.set_error("malformed MediumRequest");
  } else if (request.has_set_positions()) {
    const Scenario& scenario = core_->scenario();
    for (const proto::RobotPosition& p : request.set_positions().position()) {
      int robot =
          p.has_robot_index() ? static_cast<int>(p.robot_index()) : scenario.RobotIndex(p.robot());
      if (robot < 0 || robot >= core_->robot_count()) {
        response.set_error(
            "set_positions: no robot " +
            (p.has_robot_index() ? std::to_string(p.robot_index()) : "\"" + p.robot() + "\"") +
            " in scenario " + scenario.name);
        break;
      }
      core_->SetPosition(robot, p.position_m().x(), p.position_m().y(), p.position_m().z());
    }
    *response.mutable_status() = Status();
  } else if (request.has_get_counters()) {
    core_->RefreshKernelCounters();
    *response.mutable_status() = Status();
  } else if (request.has_subscribe_pcap()) {
    c->out += Frame(response.SerializeAsString());
    c->out += PcapFileHeader();
    const int fd = c->fd.get();
    c->subscriber_id = fanout_->AddSubscriber([this, fd](const std::string& record) {
      auto it = connections_.find(fd);
      if (it == connections_.end()) return false;
      Connection* s = it->second.get();
      if (s->out.size() + record.size() > kMaxSubscriberBacklogBytes) return false;
      s->out += record;
      Flush(s);  // Streaming: each record goes out now, not at the next wakeup.
      return true;
    });
    core_->SetAirFrameCapture(true);
    return;
  } else {
    response.set_error("empty MediumRequest");
  }
  c->out += Frame(response.SerializeAsString());
}

void ControlServer::Flush(Connection* c) {
  while (!c->out.empty()) {
    const ssize_t n = send(c->fd.get(), c->out.data(), c->out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      c->out.erase(0, n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) break;
    // Peer gone: closed on the next event (not here: Flush runs inside the
    // fan-out, which must not see its subscriber list change under it).
    c->out.clear();
    break;
  }
  const bool want_out = !c->out.empty();
  if (want_out != c->want_out) {
    loop_->Modify(c->fd.get(), EPOLLIN | EPOLLRDHUP | (want_out ? uint32_t{EPOLLOUT} : 0u));
    c->want_out = want_out;
  }
}

void ControlServer::Close(int fd) {
  auto it = connections_.find(fd);
  if (it == connections_.end()) return;
  if (it->second->subscriber_id != 0) {
    fanout_->RemoveSubscriber(it->second->subscriber_id);
    if (!fanout_->active()) core_->SetAirFrameCapture(false);
  }
  loop_->Remove(fd);
  connections_.erase(it);  // Closes its fd.
}

proto::MediumStatus ControlServer::Status() const {
  proto::MediumStatus status;
  const Scenario& scenario = core_->scenario();
  status.set_scenario(scenario.name);
  status.set_virtual_time_ns(core_->VirtualNowNs());
  for (int i = 0; i < core_->robot_count(); ++i) {
    proto::StationCounters* s = status.add_station();
    const PortCounters& port = core_->port_counters(i);
    MediumCountersToProto(core_->medium_counters(i), s);
    s->set_robot_index(i);
    s->set_robot(scenario.robots[i].name);
    s->set_attached(port.attached);
    s->set_frames_read(port.frames_read);
    s->set_oversize_dropped(port.oversize_dropped);
    s->set_runt_dropped(port.runt_dropped);
    s->set_unknown_source_dropped(port.unknown_source_dropped);
    s->set_frames_written(port.frames_written);
    s->set_write_errors(port.write_errors);
    s->set_kernel_tx_dropped(port.kernel_tx_dropped);
  }
  const LatenessStats lateness = core_->TotalLateness();
  status.set_lateness_p50_ns(lateness.p50_ns);
  status.set_lateness_p99_ns(lateness.p99_ns);
  status.set_lateness_max_ns(lateness.max_ns);
  status.set_deliveries(lateness.count);
  status.set_pcap_records(fanout_->records());
  status.set_pcap_subscriber_drops(fanout_->subscriber_drops());
  return status;
}

}  // namespace sitlnet::tapbridge

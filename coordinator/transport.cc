#include "coordinator/transport.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <openssl/crypto.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <ctime>

namespace sitlnet::coordinator {
namespace {

TransportError SystemError(std::string_view what, int err) {
  return TransportError(TransportError::Kind::kSystem, SystemErrorMessage(what, err));
}

void SetNonBlocking(int fd) {
  const int flags = fcntl(fd, F_GETFL);
  if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
    throw SystemError("set O_NONBLOCK on socket", errno);
  }
}

// Milliseconds poll() may wait before `deadline_ns`, rounded up so we never
// wake just before the deadline and spin.
int PollTimeoutMs(TimeNs deadline_ns) {
  if (deadline_ns == kNoDeadline) return -1;
  const TimeNs left = deadline_ns - MonotonicNowNs();
  if (left <= 0) return 0;
  const TimeNs ms = (left + kNsPerMs - 1) / kNsPerMs;
  return ms > INT32_MAX ? INT32_MAX : static_cast<int>(ms);
}

sockaddr_un UnixAddress(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof address.sun_path) {
    throw Error("unix socket path \"" + path + "\" must have 1.." +
                std::to_string(sizeof address.sun_path - 1) + " characters");
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

// Resolves host:port (numeric or by name) to the first IPv4/IPv6 address.
addrinfo* Resolve(const Endpoint& endpoint, bool passive) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = passive ? AI_PASSIVE : 0;
  addrinfo* result = nullptr;
  const std::string port = std::to_string(endpoint.port);
  const int rc = getaddrinfo(endpoint.host.empty() ? nullptr : endpoint.host.c_str(), port.c_str(),
                             &hints, &result);
  if (rc != 0) {
    throw TransportError(TransportError::Kind::kSystem,
                         "resolve \"" + endpoint.ToString() + "\": " + gai_strerror(rc));
  }
  return result;
}

void ConfigureTcp(int fd) {
  // Lock-step frames are small and latency-bound: Nagle would hold each END
  // back until the previous frame is acknowledged.
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  // A host that vanishes without closing (power loss, cable) must not leave
  // a connector waiting forever for its next START: keepalive probes after
  // 5 s of silence, every 1 s, 3 unanswered -> the read fails (ETIMEDOUT).
  const int idle_s = 5, interval_s = 1, count = 3;
  setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &one, sizeof one);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle_s, sizeof idle_s);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval_s, sizeof interval_s);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &count, sizeof count);
}

}  // namespace

std::string Endpoint::ToString() const {
  return kind == Kind::kUnix ? "unix:" + path : host + ":" + std::to_string(port);
}

bool IsLocalOnly(const Endpoint& endpoint) {
  if (endpoint.kind == Endpoint::Kind::kUnix) return true;
  if (endpoint.host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, endpoint.host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  std::string host = endpoint.host;
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  return inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

Endpoint ParseEndpoint(std::string_view text) {
  Endpoint endpoint;
  std::string_view rest = text;
  if (rest.starts_with("unix:")) {
    endpoint.path = std::string(rest.substr(5));
    if (endpoint.path.empty()) throw Error("endpoint \"" + std::string(text) + "\": empty path");
    return endpoint;
  }
  if (rest.starts_with("/") || rest.starts_with(".")) {
    endpoint.path = std::string(rest);
    return endpoint;
  }
  if (rest.starts_with("tcp:")) rest.remove_prefix(4);
  const size_t colon = rest.rfind(':');
  int port = -1;
  if (colon != std::string_view::npos) {
    const std::string_view digits = rest.substr(colon + 1);
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
    if (ec != std::errc() || end != digits.data() + digits.size()) port = -1;
  }
  if (colon == std::string_view::npos || port < 0 || port > 65535) {
    throw Error("endpoint \"" + std::string(text) +
                "\": expected unix:/path, /path or host:port with port 0..65535");
  }
  endpoint.kind = Endpoint::Kind::kTcp;
  endpoint.host = std::string(rest.substr(0, colon));
  // "[::1]:port" style brackets are accepted for IPv6 literals.
  if (endpoint.host.size() >= 2 && endpoint.host.front() == '[' && endpoint.host.back() == ']') {
    endpoint.host = endpoint.host.substr(1, endpoint.host.size() - 2);
  }
  endpoint.port = port;
  return endpoint;
}

//---------------------------------- Channel ---------------------------------

Channel::Channel(UniqueFd socket, FrameCodecOptions options)
    : socket_(std::move(socket)), encoder_(options), max_frame_bytes_(options.max_frame_bytes) {
  SITLNET_DEMAND(socket_.valid());
  SetNonBlocking(socket_.get());
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (getsockname(socket_.get(), reinterpret_cast<sockaddr*>(&address), &length) == 0 &&
      (address.ss_family == AF_INET || address.ss_family == AF_INET6)) {
    ConfigureTcp(socket_.get());
  }
}

bool Channel::Wait(short events, TimeNs deadline_ns, int interrupt_fd, const char* doing) {
  for (;;) {
    pollfd fds[2] = {{socket_.get(), events, 0}, {interrupt_fd, POLLIN, 0}};
    const int n = poll(fds, interrupt_fd >= 0 ? 2 : 1, PollTimeoutMs(deadline_ns));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw SystemError(std::string("poll while ") + doing, errno);
    }
    if (interrupt_fd >= 0 && (fds[1].revents & POLLIN)) return false;
    if (fds[0].revents != 0) return true;  // Ready, or an error the next call reports.
    if (n == 0 && deadline_ns != kNoDeadline && MonotonicNowNs() >= deadline_ns) {
      throw TransportError(TransportError::Kind::kTimeout, std::string("timed out ") + doing);
    }
  }
}

void Channel::AuthenticateMessages(const std::string& send_key, const std::string& receive_key) {
  send_tagger_ = std::make_unique<MessageTagger>(send_key);
  receive_tagger_ = std::make_unique<MessageTagger>(receive_key);
  transcript_.reset();  // The tags take over from here.
}

void Channel::RecordTranscript() { transcript_ = std::make_unique<TranscriptHash>(); }

std::string Channel::TranscriptDigest() const {
  SITLNET_DEMAND(transcript_ != nullptr);
  return transcript_->Digest();
}

void Channel::Send(const proto::coord::CoordinatorMessage& message, TimeNs deadline_ns) {
  std::string_view frame = encoder_.Encode(message);
  if (encoder_.last_encoding() == FrameEncoding::kZlib) ++compressed_frames_sent_;
  if (transcript_) transcript_->Add(frame);
  if (send_tagger_) {
    // One buffer, one send: a frame and its tag leave in the same segment when they fit.
    tagged_frame_.assign(frame);
    tagged_frame_.resize(frame.size() + kMessageTagBytes);
    send_tagger_->TagNext(frame,
                          reinterpret_cast<unsigned char*>(tagged_frame_.data() + frame.size()));
    frame = tagged_frame_;
  }
  size_t done = 0;
  while (done < frame.size()) {
    const ssize_t n = send(socket_.get(), frame.data() + done, frame.size() - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      Wait(POLLOUT, deadline_ns, -1, "sending a frame");
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EPIPE || errno == ECONNRESET)) {
      throw TransportError(TransportError::Kind::kClosed, "peer closed the connection");
    }
    throw SystemError("send frame", errno);
  }
  bytes_sent_ += frame.size();
}

bool Channel::FillAtLeast(size_t bytes, TimeNs deadline_ns, int interrupt_fd) {
  TimeNs spin_until_ns = -1;  // Set at the first empty read of this call.
  while (inbox_end_ - inbox_begin_ < bytes) {
    if (inbox_begin_ > 0) {  // Compact so the buffer does not grow without bound.
      std::memmove(inbox_.data(), inbox_.data() + inbox_begin_, inbox_end_ - inbox_begin_);
      inbox_end_ -= inbox_begin_;
      inbox_begin_ = 0;
    }
    // Read what is needed, or more (64 KiB of room) so the next frame is
    // often already here: one recv per frame in the steady state.
    const size_t room = std::max(bytes, size_t{64} << 10);
    if (inbox_.size() < room) inbox_.resize(room);
    const ssize_t n =
        recv(socket_.get(), inbox_.data() + inbox_end_, inbox_.size() - inbox_end_, 0);
    if (n > 0) {
      inbox_end_ += static_cast<size_t>(n);
      continue;
    }
    if (n == 0) {
      throw TransportError(TransportError::Kind::kClosed,
                           inbox_end_ == 0 ? "peer closed the connection"
                                           : "peer closed the connection in the middle of a frame");
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      // Poll the socket for a while before sleeping in poll(): in lock-step
      // the answer often comes within microseconds, and waking a sleeping
      // thread costs tens of microseconds on this machine class (measured,
      // docs/performance.md).
      if (spin_ns_ > 0) {
        const TimeNs now = MonotonicNowNs();
        if (spin_until_ns < 0) spin_until_ns = now + spin_ns_;
        if (now < spin_until_ns && now < deadline_ns) {
          __builtin_ia32_pause();
          continue;
        }
      }
      if (!Wait(POLLIN, deadline_ns, interrupt_fd, "waiting for a frame")) return false;
      continue;
    }
    if (errno == EINTR) continue;
    if (errno == ECONNRESET) {
      throw TransportError(TransportError::Kind::kClosed, "peer reset the connection");
    }
    if (errno == ETIMEDOUT) {
      throw TransportError(TransportError::Kind::kClosed,
                           "peer stopped answering TCP keepalive probes (host gone?)");
    }
    throw SystemError("recv frame", errno);
  }
  return true;
}

bool Channel::Receive(proto::coord::CoordinatorMessage* message, TimeNs deadline_ns,
                      int interrupt_fd) {
  if (!FillAtLeast(kFrameHeaderBytes, deadline_ns, interrupt_fd)) return false;
  FrameEncoding encoding{};
  size_t body = 0;
  try {
    body = ParseFrameHeader(reinterpret_cast<const uint8_t*>(inbox_.data() + inbox_begin_),
                            max_frame_bytes_, &encoding);
  } catch (const Error& e) {
    throw TransportError(TransportError::Kind::kBadFrame, e.what());
  }
  // Once a header is in, the rest of the frame is not interruptible: leaving
  // half a frame consumed would desynchronize the stream.
  const size_t tag_bytes = receive_tagger_ ? kMessageTagBytes : 0;
  FillAtLeast(kFrameHeaderBytes + body + tag_bytes, deadline_ns, -1);
  if (receive_tagger_) {
    const uint64_t sequence = receive_tagger_->count();
    const std::string_view frame(inbox_.data() + inbox_begin_, kFrameHeaderBytes + body);
    unsigned char expected[kMessageTagBytes];
    receive_tagger_->TagNext(frame, expected);
    if (CRYPTO_memcmp(expected, frame.data() + frame.size(), kMessageTagBytes) != 0) {
      throw TransportError(TransportError::Kind::kBadFrame,
                           "message " + std::to_string(sequence) +
                               " of the connection failed authentication (changed, added, "
                               "dropped or repeated on the way)");
    }
  }
  if (transcript_)
    transcript_->Add(std::string_view(inbox_.data() + inbox_begin_, kFrameHeaderBytes + body));
  const std::string_view body_bytes(inbox_.data() + inbox_begin_ + kFrameHeaderBytes, body);
  inbox_begin_ += kFrameHeaderBytes + body + tag_bytes;
  bytes_received_ += kFrameHeaderBytes + body + tag_bytes;
  if (inbox_begin_ == inbox_end_) inbox_begin_ = inbox_end_ = 0;  // Decoded below before reuse.
  try {
    DecodeFrameBody(encoding, body_bytes, max_frame_bytes_, &scratch_, message);
  } catch (const Error& e) {
    throw TransportError(TransportError::Kind::kBadFrame, e.what());
  }
  return true;
}

//--------------------------------- Listener ---------------------------------

Listener::Listener(const Endpoint& endpoint) : endpoint_(endpoint) {
  if (endpoint.kind == Endpoint::Kind::kUnix) {
    const sockaddr_un address = UnixAddress(endpoint.path);
    socket_ = UniqueFd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (!socket_.valid()) throw SystemError("create unix socket", errno);
    unlink(endpoint.path.c_str());  // A stale socket from a killed run.
    if (bind(socket_.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) < 0) {
      throw SystemError("bind unix socket \"" + endpoint.path + "\"", errno);
    }
    // Owner only, whatever the umask: robots share the host's filesystem, and connecting to a
    // Unix socket needs write permission on it (docs/security.md).
    if (chmod(endpoint.path.c_str(), 0600) != 0) {
      throw SystemError("chmod 0600 unix socket \"" + endpoint.path + "\"", errno);
    }
  } else {
    addrinfo* info = Resolve(endpoint, /*passive=*/true);
    socket_ = UniqueFd(socket(info->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0));
    const int one = 1;
    if (socket_.valid()) setsockopt(socket_.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    const int rc = socket_.valid() ? bind(socket_.get(), info->ai_addr, info->ai_addrlen) : -1;
    const int err = errno;
    freeaddrinfo(info);
    if (rc < 0) throw SystemError("bind tcp \"" + endpoint.ToString() + "\"", err);
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    getsockname(socket_.get(), reinterpret_cast<sockaddr*>(&bound), &length);
    endpoint_.port =
        ntohs(bound.ss_family == AF_INET ? reinterpret_cast<sockaddr_in*>(&bound)->sin_port
                                         : reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port);
  }
  if (listen(socket_.get(), 16) < 0) throw SystemError("listen on " + endpoint_.ToString(), errno);
  SetNonBlocking(socket_.get());
}

Listener::~Listener() {
  if (endpoint_.kind == Endpoint::Kind::kUnix && socket_.valid()) unlink(endpoint_.path.c_str());
}

UniqueFd Listener::Accept(TimeNs deadline_ns, int interrupt_fd) {
  for (;;) {
    const int fd = accept4(socket_.get(), nullptr, nullptr, SOCK_CLOEXEC);
    if (fd >= 0) return UniqueFd(fd);
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      throw SystemError("accept on " + endpoint_.ToString(), errno);
    }
    pollfd fds[2] = {{socket_.get(), POLLIN, 0}, {interrupt_fd, POLLIN, 0}};
    const int n = poll(fds, interrupt_fd >= 0 ? 2 : 1, PollTimeoutMs(deadline_ns));
    if (n < 0 && errno != EINTR) throw SystemError("poll on " + endpoint_.ToString(), errno);
    if (interrupt_fd >= 0 && (fds[1].revents & POLLIN)) return UniqueFd();
    if (n == 0 && deadline_ns != kNoDeadline && MonotonicNowNs() >= deadline_ns) {
      throw TransportError(TransportError::Kind::kTimeout,
                           "timed out waiting for a connection on " + endpoint_.ToString());
    }
  }
}

//---------------------------------- Connect ---------------------------------

UniqueFd Connect(const Endpoint& endpoint, TimeNs deadline_ns) {
  for (;;) {
    UniqueFd fd;
    int rc = -1;
    int err = 0;
    if (endpoint.kind == Endpoint::Kind::kUnix) {
      const sockaddr_un address = UnixAddress(endpoint.path);
      fd = UniqueFd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
      rc = connect(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address);
      err = errno;
    } else {
      addrinfo* info = Resolve(endpoint, /*passive=*/false);
      // Non-blocking, so that a host that drops the SYN (down, filtered)
      // costs the deadline, not the kernel's ~2 min of SYN retries.
      fd = UniqueFd(socket(info->ai_family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
      rc = connect(fd.get(), info->ai_addr, info->ai_addrlen);
      err = errno;
      freeaddrinfo(info);
      if (rc < 0 && err == EINPROGRESS) {
        pollfd wait{fd.get(), POLLOUT, 0};
        const int n = poll(&wait, 1, PollTimeoutMs(deadline_ns));
        if (n == 0) {
          throw TransportError(TransportError::Kind::kTimeout,
                               "connect to " + endpoint.ToString() +
                                   ": no answer before the deadline (host down or filtered?)");
        }
        socklen_t length = sizeof err;
        if (n < 0 || getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &length) < 0) err = errno;
        rc = err == 0 ? 0 : -1;
      }
      if (rc == 0) fcntl(fd.get(), F_SETFL, fcntl(fd.get(), F_GETFL) & ~O_NONBLOCK);
    }
    if (rc == 0) return fd;
    const bool not_yet = err == ENOENT || err == ECONNREFUSED;
    if (!not_yet || MonotonicNowNs() >= deadline_ns) {
      throw TransportError(not_yet ? TransportError::Kind::kTimeout : TransportError::Kind::kSystem,
                           SystemErrorMessage("connect to " + endpoint.ToString(), err));
    }
    // The coordinator may not be listening yet (started in either order):
    // retry at a coarse interval, this is a one-time startup wait.
    timespec pause{0, 10 * kNsPerMs};
    nanosleep(&pause, nullptr);
  }
}

std::pair<UniqueFd, UniqueFd> SocketPair() {
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) < 0) {
    throw SystemError("socketpair", errno);
  }
  return {UniqueFd(fds[0]), UniqueFd(fds[1])};
}

}  // namespace sitlnet::coordinator

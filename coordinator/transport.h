// Stream transport for coordinator messages: Unix domain sockets (default,
// one host) and TCP (a connector on another host), framed by frame_codec.h.
// Every blocking call takes an absolute deadline (CLOCK_MONOTONIC ns) and an
// optional interrupt fd (a StopSignal), so nothing here can hang forever.
#ifndef SITLNET_COORDINATOR_TRANSPORT_H_
#define SITLNET_COORDINATOR_TRANSPORT_H_

#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "common/common.h"
#include "coordinator/authentication.h"
#include "coordinator/frame_codec.h"

namespace sitlnet::coordinator {

// Deadline meaning "wait forever" (still interruptible).
inline constexpr TimeNs kNoDeadline = INT64_MAX;

// Where to listen or connect: "unix:/path", "/path" or "./path" (a Unix
// socket), or "host:port" / "tcp:host:port" (TCP; host may be a name).
struct Endpoint {
  enum class Kind { kUnix, kTcp };
  Kind kind = Kind::kUnix;
  std::string path;  // kUnix
  std::string host;  // kTcp
  int port = 0;      // kTcp; 0 when listening: any free port
  std::string ToString() const;
};
// Throws Error naming `text` if it is neither form.
Endpoint ParseEndpoint(std::string_view text);
// True if only this host can connect to `endpoint`: a Unix socket, or TCP on a loopback
// address (127.0.0.0/8, ::1, "localhost").
bool IsLocalOnly(const Endpoint& endpoint);

// Why a transport call failed; the message says it in words.
class TransportError : public Error {
 public:
  enum class Kind { kTimeout, kClosed, kBadFrame, kSystem };
  TransportError(Kind kind, const std::string& message) : Error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

// One connection carrying CoordinatorMessages both ways. Not thread-safe.
class Channel {
 public:
  // Takes a connected stream socket; makes it non-blocking (TCP: no Nagle).
  Channel(UniqueFd socket, FrameCodecOptions options = {});

  // Sends one message; throws TransportError (kTimeout, kClosed, kSystem).
  void Send(const proto::coord::CoordinatorMessage& message, TimeNs deadline_ns = kNoDeadline);

  // Receives one message. Returns false if `interrupt_fd` became readable
  // first (nothing consumed); throws TransportError on timeout, peer close,
  // bad frame or system error.
  bool Receive(proto::coord::CoordinatorMessage* message, TimeNs deadline_ns = kNoDeadline,
               int interrupt_fd = -1);

  // From now on every frame sent is followed by its tag under `send_key`, and every frame
  // received must be followed by a valid tag under `receive_key` (authentication.h): both ends
  // call it once the handshake has proven the shared secret. A frame whose tag does not verify
  // throws TransportError(kBadFrame), and nothing of it is used.
  void AuthenticateMessages(const std::string& send_key, const std::string& receive_key);
  // From now until AuthenticateMessages, every frame sent or received goes into a SHA-256, the
  // handshake's transcript (authentication.h), which TranscriptDigest() returns so far.
  void RecordTranscript();
  std::string TranscriptDigest() const;
  bool authenticates_messages() const { return send_tagger_ != nullptr; }

  int fd() const { return socket_.get(); }
  // Receive() polls the socket without sleeping for up to this long before
  // it blocks (0: block at once). Trades CPU for wake-up latency.
  void set_spin_ns(TimeNs spin_ns) { spin_ns_ = spin_ns; }
  // Frames sent compressed so far (for benchmarks and tests).
  uint64_t compressed_frames_sent() const { return compressed_frames_sent_; }
  // Bytes that crossed the socket as whole frames (header, body and tag), each way.
  uint64_t bytes_sent() const { return bytes_sent_; }
  uint64_t bytes_received() const { return bytes_received_; }

 private:
  // Waits until fd is ready for `events`; false if interrupt_fd fired.
  bool Wait(short events, TimeNs deadline_ns, int interrupt_fd, const char* doing);
  bool FillAtLeast(size_t bytes, TimeNs deadline_ns, int interrupt_fd);

  UniqueFd socket_;
  FrameEncoder encoder_;
  size_t max_frame_bytes_;
  std::string inbox_;  // Received, unconsumed bytes are [inbox_begin_, inbox_end_).
  size_t inbox_begin_ = 0;
  size_t inbox_end_ = 0;
  FrameScratch scratch_;
  TimeNs spin_ns_ = 0;
  std::unique_ptr<MessageTagger> send_tagger_;     // Set by AuthenticateMessages.
  std::unique_ptr<MessageTagger> receive_tagger_;  // Set by AuthenticateMessages.
  std::string tagged_frame_;                       // A frame and its tag, as sent.
  std::unique_ptr<TranscriptHash> transcript_;     // Set by RecordTranscript.
  uint64_t compressed_frames_sent_ = 0;
  uint64_t bytes_sent_ = 0;
  uint64_t bytes_received_ = 0;
};

// A listening socket. A Unix socket path is unlinked before bind and on
// destruction.
class Listener {
 public:
  explicit Listener(const Endpoint& endpoint);
  ~Listener();
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;
  // Accepts one connection; throws TransportError(kTimeout) at the deadline;
  // returns an invalid UniqueFd if interrupt_fd fired.
  UniqueFd Accept(TimeNs deadline_ns = kNoDeadline, int interrupt_fd = -1);
  // The bound endpoint (TCP: with the actual port when 0 was asked).
  const Endpoint& endpoint() const { return endpoint_; }
  int fd() const { return socket_.get(); }

 private:
  Endpoint endpoint_;
  UniqueFd socket_;
};

// Connects to a listening coordinator, retrying until the deadline while the
// listener does not exist yet (ENOENT, ECONNREFUSED). Throws TransportError.
UniqueFd Connect(const Endpoint& endpoint, TimeNs deadline_ns);

// A connected pair of Unix stream sockets (tests, in-process use).
std::pair<UniqueFd, UniqueFd> SocketPair();

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_TRANSPORT_H_

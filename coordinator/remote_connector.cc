// Socket side of connectors: the coordinator's RemoteConnector, its
// handshake, and ServeCoordinator() that runs inside a connector process.
#include "coordinator/remote_connector.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "coordinator/authentication.h"

namespace sitlnet::coordinator {
namespace {

using proto::coord::CoordinatorMessage;

// Longest wait for a new connection's Hello.
constexpr TimeNs kHelloTimeoutNs = 2 * kNsPerS;

std::string Ms(TimeNs ns) { return std::to_string(ns / kNsPerMs) + " ms"; }

std::string Hex(uint64_t value) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

const char* KindName(CoordinatorMessage::KindCase kind) {
  switch (kind) {
    case CoordinatorMessage::kHello:
      return "Hello";
    case CoordinatorMessage::kWelcome:
      return "Welcome";
    case CoordinatorMessage::kChallenge:
      return "Challenge";
    case CoordinatorMessage::kProof:
      return "Proof";
    case CoordinatorMessage::kStart:
      return "Start";
    case CoordinatorMessage::kEnd:
      return "End";
    case CoordinatorMessage::kStop:
      return "Stop";
    case CoordinatorMessage::kError:
      return "Error";
    case CoordinatorMessage::kCommandsCollected:
      return "CommandsCollected";
    default:
      return "an empty message";
  }
}

std::string PrintableName(const std::string& name) {
  // Maybe a stranger's: printable ASCII only, 64 bytes at most.
  std::string printable = name.substr(0, 64);
  for (char& c : printable) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return printable;
}

void SendErrorQuietly(Channel& channel, const std::string& message) {
  CoordinatorMessage error;
  error.mutable_error()->set_message(message);
  try {
    channel.Send(error, MonotonicNowNs() + kNsPerS);
  } catch (const Error&) {
  }
}

RemoteConnector::RemoteConnector(std::string name, Role role, Channel channel,
                                 proto::coord::Poses poses, std::string description)
    : Connector(std::move(name), role, std::move(description)),
      channel_(std::move(channel)),
      poses_(std::move(poses)) {}

void RemoteConnector::Begin(const proto::coord::Start& start, const WaitLimits& limits) {
  *out_.mutable_start() = start;
  outstanding_ = true;
  outstanding_iteration_ = start.iteration();
  const uint64_t sent_before = channel_.bytes_sent();
  const TimeNs sending_ns = MonotonicNowNs();  // The round trip includes encoding and tagging.
  try {
    channel_.Send(out_, limits.deadline_ns);
    meter_.StartSent(sending_ns, channel_.bytes_sent() - sent_before);
  } catch (const TransportError& e) {
    throw Error(Describe() + ": sending START of iteration " + std::to_string(start.iteration()) +
                ": " + Explain(e));
  }
}

bool RemoteConnector::AwaitCommandsCollected(uint64_t iteration, const WaitLimits& limits) {
  if (!ReceiveExpected(iteration, "CommandsCollected", limits)) return false;
  // A physics connector without robots in lock-step may finish without
  // reporting CommandsCollected: its END then opens the gate too.
  if (in_.kind_case() == CoordinatorMessage::kEnd && in_.end().iteration() == iteration) {
    early_end_ = true;
    return true;
  }
  if (in_.kind_case() != CoordinatorMessage::kCommandsCollected ||
      in_.commands_collected().iteration() != iteration) {
    throw Unexpected(iteration, "CommandsCollected");
  }
  return true;
}

std::string RemoteConnector::TakeCommandsCollectedPayload() {
  std::string payload;
  if (in_.has_commands_collected()) {
    payload.swap(*in_.mutable_commands_collected()->mutable_payload());
  }
  return payload;
}

bool RemoteConnector::Finish(uint64_t iteration, proto::coord::End* end, const WaitLimits& limits) {
  if (early_end_) {
    early_end_ = false;  // Received by AwaitCommandsCollected; still in in_.
  } else if (!ReceiveExpected(iteration, "END", limits)) {
    return false;
  }
  if (in_.kind_case() != CoordinatorMessage::kEnd || in_.end().iteration() != iteration) {
    throw Unexpected(iteration, "END");
  }
  meter_.EndReceived(MonotonicNowNs());
  end->Swap(in_.mutable_end());
  outstanding_ = false;
  return true;
}

void RemoteConnector::Stop(const std::string& reason) {
  // An iteration still running (the run was interrupted): let it finish
  // and drop its END, so the connector sees an orderly Stop rather than a
  // closed socket when it answers.
  const TimeNs deadline = MonotonicNowNs() + kDrainTimeoutNs;
  try {
    while (outstanding_ && channel_.Receive(&in_, deadline)) {
      if (in_.has_error() || (in_.has_end() && in_.end().iteration() == outstanding_iteration_)) {
        outstanding_ = false;
      }
    }
  } catch (const Error&) {
    // Gone or stuck: Stop below is best effort either way.
  }
  CoordinatorMessage stop;
  stop.mutable_stop()->set_reason(reason);
  try {
    channel_.Send(stop, MonotonicNowNs() + kNsPerS);
  } catch (const Error&) {
    // Already gone: nothing to tell it.
  }
}

std::string RemoteConnector::Explain(const TransportError& e) const {
  if (e.kind() == TransportError::Kind::kClosed) {
    return std::string(e.what()) +
           (role() == Role::kNode ? " (node crashed or exited)" : " (connector crashed or exited)");
  }
  return e.what();
}

// Receives the answer to START of `iteration`; turns transport failures
// into messages naming this connector.
bool RemoteConnector::ReceiveExpected(uint64_t iteration, const char* what,
                                      const WaitLimits& limits) {
  const uint64_t received_before = channel_.bytes_received();
  try {
    if (!channel_.Receive(&in_, limits.deadline_ns, limits.interrupt_fd)) return false;
    meter_.Received(channel_.bytes_received() - received_before);
  } catch (const TransportError& e) {
    outstanding_ = false;  // Failed or stuck: Stop() must not wait for it.
    const std::string k = std::to_string(iteration);
    if (e.kind() == TransportError::Kind::kTimeout) {
      throw Error(Describe() + " did not answer START of iteration " + k + " with " + what +
                  " within " + Ms(limits.timeout_ns));
    }
    throw Error(Describe() + " failed during iteration " + k + ": " + Explain(e));
  }
  if (in_.kind_case() == CoordinatorMessage::kError) {
    outstanding_ = false;
    throw Error(Describe() + " reported an error in iteration " + std::to_string(iteration) + ": " +
                in_.error().message());
  }
  return true;
}

Error RemoteConnector::Unexpected(uint64_t iteration, const char* what) const {
  std::string got = KindName(in_.kind_case());
  if (in_.has_end()) got += " of iteration " + std::to_string(in_.end().iteration());
  if (in_.has_commands_collected()) {
    got += " of iteration " + std::to_string(in_.commands_collected().iteration());
  }
  return Error(Describe() + ": protocol error: expected " + what + " of iteration " +
               std::to_string(iteration) + ", got " + got);
}

namespace {

// The coordinator's side of the shared-secret handshake: Challenge (its nonce and proof), then
// the connector's Proof. A connector that cannot prove the secret is a stray connection.
void Authenticate(Channel& channel, const std::string& secret, const std::string& their_nonce,
                  const std::string& who, TimeNs deadline_ns, int interrupt_fd) {
  std::string failure;
  if (secret.empty()) {
    failure = who +
              " wants to authenticate with a shared secret, but this coordinator has none "
              "(--secret-file)";
  } else if (their_nonce.size() != kNonceBytes) {
    failure = who +
              " did not authenticate: this coordinator needs the shared secret "
              "(--secret-file on both ends)";
  }
  if (failure.empty()) {
    // Each proof covers both nonces and the transcript so far (the Hello; the Hello and the
    // Challenge), so a Hello changed on the way fails both.
    const std::string nonce = RandomNonce();
    CoordinatorMessage challenge;
    challenge.mutable_challenge()->set_nonce(nonce);
    challenge.mutable_challenge()->set_proof(
        ProofOf(secret, "sitlnet coordinator", their_nonce, nonce + channel.TranscriptDigest()));
    CoordinatorMessage proof;
    std::string hello_and_challenge;
    try {
      channel.Send(challenge, deadline_ns);
      hello_and_challenge = channel.TranscriptDigest();
      if (!channel.Receive(&proof, deadline_ns, interrupt_fd)) {
        throw StrayConnectionError(who + ": interrupted while authenticating");
      }
    } catch (const TransportError& e) {
      throw StrayConnectionError(who + ": authenticating: " + e.what());
    }
    if (!proof.has_proof() ||
        !SameProof(proof.proof().proof(), ProofOf(secret, "sitlnet connector", nonce,
                                                  their_nonce + hello_and_challenge))) {
      failure = who + " failed to prove the shared secret (a different --secret-file?)";
    } else {
      // Everything after the proof is tagged: the handshake binds the rest of the connection.
      const SessionKeys keys = DeriveSessionKeys(secret, nonce, their_nonce + hello_and_challenge);
      channel.AuthenticateMessages(keys.coordinator_to_connector, keys.connector_to_coordinator);
    }
  }
  if (failure.empty()) return;
  SendErrorQuietly(channel, failure);
  throw StrayConnectionError(failure);
}

}  // namespace

namespace {

std::unique_ptr<Connector> ConnectorOf(AcceptedPeer peer) {
  return std::make_unique<RemoteConnector>(std::move(peer.name), peer.role, std::move(peer.channel),
                                           std::move(*peer.hello.mutable_initial_poses()));
}

}  // namespace

std::optional<AcceptedPeer> AcceptPeer(Channel channel, const HandshakeExpectation& expect,
                                       const WaitLimits& limits) {
  // With a secret, the Hello is part of what the proofs cover (Authenticate).
  if (!expect.secret.empty()) channel.RecordTranscript();
  CoordinatorMessage hello;
  // A connector sends Hello right after connecting; waiting long for one
  // would let a silent stray connection hold the real connectors back.
  const TimeNs hello_deadline_ns = std::min(limits.deadline_ns, MonotonicNowNs() + kHelloTimeoutNs);
  try {
    if (!channel.Receive(&hello, hello_deadline_ns, limits.interrupt_fd)) return std::nullopt;
  } catch (const TransportError& e) {
    throw StrayConnectionError(std::string("connector handshake: ") + e.what());
  }
  if (!hello.has_hello()) {
    const std::string what =
        std::string("connector handshake: expected Hello, got ") + KindName(hello.kind_case());
    SendErrorQuietly(channel, what);
    throw StrayConnectionError(what);
  }
  const proto::coord::Hello& h = hello.hello();
  const Role role = h.role() == proto::coord::ROLE_NETWORK ? Role::kNetwork
                    : h.role() == proto::coord::ROLE_NODE  ? Role::kNode
                                                           : Role::kPhysics;
  std::string name = PrintableName(h.connector_name());
  const std::string who =
      role == Role::kNode ? "node '" + name + "'" : RoleName(role) + " connector '" + name + "'";
  // Authentication first: a peer without the secret learns nothing of the run.
  if (!expect.secret.empty() || !h.nonce().empty()) {
    Authenticate(channel, expect.secret, h.nonce(), who, hello_deadline_ns, limits.interrupt_fd);
  }
  std::string refusal;
  if (h.role() != proto::coord::ROLE_PHYSICS && h.role() != proto::coord::ROLE_NETWORK &&
      h.role() != proto::coord::ROLE_NODE) {
    refusal = "connector '" + name + "' has no role (physics or network)";
  } else if (h.protocol_version() != kProtocolVersion) {
    refusal = who + " speaks protocol version " + std::to_string(h.protocol_version()) +
              ", the coordinator " + std::to_string(kProtocolVersion);
  } else if (expect.role && role != *expect.role) {
    refusal = who + " connected, but this coordinator waits for a " + RoleName(*expect.role) +
              (*expect.role == Role::kNode ? "" : " connector");
  } else if (!expect.role && role == Role::kNode) {
    refusal = who + " connected, but this coordinator runs no fleet (its scenario has no nodes)";
  } else if (h.scenario_hash() != expect.scenario_hash) {
    refusal = who + " loaded a different scenario: hash " + Hex(h.scenario_hash()) +
              ", the coordinator's is " + Hex(expect.scenario_hash);
  } else if (expect.refuse_hello) {
    refusal = expect.refuse_hello(h);
  }
  if (!refusal.empty()) {
    SendErrorQuietly(channel, refusal);
    throw Error(refusal);
  }
  CoordinatorMessage welcome;
  welcome.mutable_welcome()->set_protocol_version(kProtocolVersion);
  welcome.mutable_welcome()->set_iteration_ns(expect.iteration_ns);
  welcome.mutable_welcome()->set_lockstep_robots(expect.lockstep_robots);
  try {
    channel.Send(welcome, limits.deadline_ns);
  } catch (const TransportError& e) {
    throw Error(who + ": sending Welcome: " + e.what());
  }
  AcceptedPeer peer{std::move(channel), {}, role, std::move(name)};
  peer.hello.Swap(hello.mutable_hello());
  return peer;
}

std::unique_ptr<Connector> AcceptConnector(Channel channel, const HandshakeExpectation& expect,
                                           const WaitLimits& limits) {
  std::optional<AcceptedPeer> peer = AcceptPeer(std::move(channel), expect, limits);
  if (!peer) return nullptr;
  return ConnectorOf(std::move(*peer));
}

namespace {

// The handshakes of accepted connections, each on a thread of its own, so that a connection that
// says nothing, or stops half-way, holds back no other: each still ends at its own Hello deadline
// (kHelloTimeoutNs). At most kMaxConcurrentHandshakes run at once; AcceptUntil accepts no more
// while they do (the next connections wait in the listener's backlog).
class ConcurrentHandshakes {
 public:
  struct Outcome {
    std::optional<AcceptedPeer> peer;  // Accepted; or none, and one of:
    std::string stray;                 // a stray connection's warning,
    std::exception_ptr refusal;        // a refused connector's Error, to pass on.
  };
  static constexpr size_t kMaxConcurrentHandshakes = 16;

  ConcurrentHandshakes(const HandshakeExpectation& expect, const WaitLimits& limits,
                       FrameCodecOptions codec, TimeNs spin_ns)
      : expect_(expect),
        limits_(limits),
        codec_(codec),
        spin_ns_(spin_ns),
        cancel_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)),
        ready_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
    if (!cancel_.valid() || !ready_.valid()) throw Error(SystemErrorMessage("eventfd", errno));
    limits_.interrupt_fd = cancel_.get();  // The caller watches its own interrupt.
  }
  // Ends the handshakes still under way and waits for them: their sockets are shut down, which
  // also ends a read in the middle of a frame (where the cancel fd is not watched).
  ~ConcurrentHandshakes() {
    {
      std::lock_guard lock(mutex_);
      for (const auto& [id, socket] : watched_) shutdown(socket, SHUT_RDWR);
    }
    Notify(cancel_.get());
    for (auto& [id, thread] : threads_) thread.join();
    for (const auto& [id, socket] : watched_) close(socket);
  }
  ConcurrentHandshakes(const ConcurrentHandshakes&) = delete;
  ConcurrentHandshakes& operator=(const ConcurrentHandshakes&) = delete;

  // Readable when an outcome is waiting for TakeFinished.
  int ready_fd() const { return ready_.get(); }

  bool HasRoom() {
    std::lock_guard lock(mutex_);
    return threads_.size() - done_.size() < kMaxConcurrentHandshakes;
  }

  void Start(UniqueFd fd) {
    std::lock_guard lock(mutex_);
    const uint64_t id = next_id_++;
    // A copy of the descriptor, ours until the thread is done, for the destructor's shutdown:
    // the thread's own may be closed (and its number reused) at any time.
    const int watch = fcntl(fd.get(), F_DUPFD_CLOEXEC, 0);
    if (watch >= 0) watched_.emplace(id, watch);
    threads_.emplace(id, std::thread([this, id, fd = std::move(fd)]() mutable {
                       Handshake(id, std::move(fd));
                     }));
  }

  std::vector<Outcome> TakeFinished() {
    uint64_t count = 0;
    while (read(ready_.get(), &count, sizeof count) < 0 && errno == EINTR) {
    }
    std::vector<Outcome> outcomes;
    std::vector<uint64_t> done;
    {
      std::lock_guard lock(mutex_);
      outcomes.swap(finished_);
      done.swap(done_);
    }
    for (uint64_t id : done) {  // Their threads have returned or are about to.
      auto thread = threads_.find(id);
      thread->second.join();
      threads_.erase(thread);
    }
    return outcomes;
  }

 private:
  // A thread's work: the handshake, then its outcome for TakeFinished.
  void Handshake(uint64_t id, UniqueFd fd) {
    Outcome outcome;
    try {
      Channel channel(std::move(fd), codec_);
      channel.set_spin_ns(spin_ns_);
      outcome.peer = AcceptPeer(std::move(channel), expect_, limits_);
    } catch (const StrayConnectionError& e) {
      outcome.stray = e.what();
    } catch (...) {
      outcome.refusal = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    if (auto watch = watched_.find(id); watch != watched_.end()) {
      close(watch->second);  // Before the outcome is out: an accepted socket is never shut.
      watched_.erase(watch);
    }
    if (outcome.peer || !outcome.stray.empty() || outcome.refusal) {
      finished_.push_back(std::move(outcome));
    }
    done_.push_back(id);
    Notify(ready_.get());
  }

  static void Notify(int fd) {
    const uint64_t one = 1;
    while (write(fd, &one, sizeof one) < 0 && errno == EINTR) {
    }
  }

  const HandshakeExpectation expect_;
  WaitLimits limits_;
  const FrameCodecOptions codec_;
  const TimeNs spin_ns_;
  UniqueFd cancel_;
  UniqueFd ready_;
  std::mutex mutex_;
  std::map<uint64_t, std::thread> threads_;  // Joined by TakeFinished once done, or at the end.
  std::map<uint64_t, int> watched_;          // Copies of the sockets of handshakes under way.
  std::vector<uint64_t> done_;               // Threads that returned, not yet joined.
  std::vector<Outcome> finished_;
  uint64_t next_id_ = 0;
};

void WarnIgnored(const Listener& listener, const std::string& why) {
  std::fprintf(stderr, "sitlnet: warning: ignored a connection on %s: %s\n",
               listener.endpoint().ToString().c_str(), why.c_str());
}

}  // namespace

bool AcceptUntil(Listener& listener, const HandshakeExpectation& expect, const WaitLimits& limits,
                 const std::function<bool(AcceptedPeer)>& take,
                 const std::function<std::string()>& missing, FrameCodecOptions codec,
                 TimeNs spin_ns) {
  ConcurrentHandshakes handshakes(expect, limits, codec, spin_ns);
  for (;;) {
    // At kMaxConcurrentHandshakes, new connections wait in the backlog (poll skips fd -1).
    pollfd fds[3] = {{handshakes.HasRoom() ? listener.fd() : -1, POLLIN, 0},
                     {handshakes.ready_fd(), POLLIN, 0},
                     {limits.interrupt_fd, POLLIN, 0}};
    const TimeNs now = MonotonicNowNs();
    if (limits.deadline_ns != kNoDeadline && now >= limits.deadline_ns) {
      throw Error(missing() + " to " + listener.endpoint().ToString() + " within " +
                  Ms(limits.timeout_ns));
    }
    const int timeout_ms =
        limits.deadline_ns == kNoDeadline
            ? -1
            : static_cast<int>(std::min<TimeNs>(
                  (limits.deadline_ns - now + kNsPerMs - 1) / kNsPerMs, INT32_MAX));
    if (poll(fds, limits.interrupt_fd >= 0 ? 3 : 2, timeout_ms) < 0) {
      if (errno == EINTR) continue;
      throw Error(SystemErrorMessage("poll on " + listener.endpoint().ToString(), errno));
    }
    if (limits.interrupt_fd >= 0 && (fds[2].revents & POLLIN)) return false;
    if (fds[1].revents & POLLIN) {
      for (ConcurrentHandshakes::Outcome& outcome : handshakes.TakeFinished()) {
        if (outcome.refusal) std::rethrow_exception(outcome.refusal);
        if (!outcome.stray.empty()) WarnIgnored(listener, outcome.stray);
        if (outcome.peer && take(std::move(*outcome.peer))) return true;
      }
    }
    if (fds[0].revents & POLLIN) {
      UniqueFd fd;
      try {
        fd = listener.Accept(MonotonicNowNs(), -1);
      } catch (const TransportError& e) {
        if (e.kind() != TransportError::Kind::kTimeout) throw;
        continue;  // The connection went away before accept.
      }
      handshakes.Start(std::move(fd));
    }
  }
}

AcceptedConnectors AcceptConnectors(Listener& listener, const HandshakeExpectation& expect,
                                    const WaitLimits& limits, FrameCodecOptions codec,
                                    TimeNs spin_ns) {
  AcceptedConnectors accepted;
  AcceptUntil(
      listener, expect, limits,
      [&](AcceptedPeer peer) {
        std::unique_ptr<Connector> connector = ConnectorOf(std::move(peer));
        auto& slot = connector->role() == Role::kPhysics ? accepted.physics : accepted.network;
        if (slot) {
          const std::string what =
              "a second " + connector->Describe() + " connected; already have " + slot->Describe();
          connector->Stop(what);
          throw Error(what);
        }
        slot = std::move(connector);
        return accepted.physics && accepted.network;
      },
      [&] {
        return std::string("no ") +
               (!accepted.physics && !accepted.network ? "physics and network"
                : !accepted.physics                    ? "physics"
                                                       : "network") +
               " connector connected";
      },
      codec, spin_ns);
  return accepted;
}

std::unique_ptr<Connector> AcceptConnectorOfRole(Listener& listener, Role role,
                                                 HandshakeExpectation expect,
                                                 const WaitLimits& limits) {
  expect.role = role;
  std::unique_ptr<Connector> accepted;
  AcceptUntil(
      listener, expect, limits,
      [&](AcceptedPeer peer) {
        accepted = ConnectorOf(std::move(peer));
        return true;
      },
      [&] { return "no " + RoleName(role) + " connector connected"; });
  return accepted;
}

//----------------------------- Connector process ----------------------------

namespace {
class RemoteContext final : public IterationContext {
 public:
  RemoteContext(Channel& channel, uint64_t iteration) : channel_(channel), iteration_(iteration) {}
  void CommandsCollected() override { CommandsCollectedWithPayload({}); }
  void CommandsCollectedWithPayload(std::string payload) override {
    CoordinatorMessage message;
    message.mutable_commands_collected()->set_iteration(iteration_);
    message.mutable_commands_collected()->set_payload(std::move(payload));
    channel_.Send(message);
  }

 private:
  Channel& channel_;
  uint64_t iteration_;
};
}  // namespace

std::string ServeCoordinator(Channel& channel, Simulator& simulator,
                             const ConnectorIdentity& identity, TimeNs handshake_timeout_ns,
                             int interrupt_fd) {
  proto::coord::Hello hello;
  *hello.mutable_initial_poses() = simulator.InitialPoses();
  if (!HandshakeWithCoordinator(channel, identity, hello, handshake_timeout_ns, interrupt_fd)) {
    return "interrupted";
  }
  return ServeIterations(channel, simulator, interrupt_fd);
}

std::optional<proto::coord::Welcome> HandshakeWithCoordinator(
    Channel& channel, const ConnectorIdentity& identity, const proto::coord::Hello& hello_extra,
    TimeNs handshake_timeout_ns, int interrupt_fd) {
  CoordinatorMessage out;
  proto::coord::Hello* hello = out.mutable_hello();
  *hello = hello_extra;
  hello->set_protocol_version(kProtocolVersion);
  hello->set_scenario_hash(identity.scenario_hash);
  hello->set_role(identity.role == Role::kPhysics   ? proto::coord::ROLE_PHYSICS
                  : identity.role == Role::kNetwork ? proto::coord::ROLE_NETWORK
                                                    : proto::coord::ROLE_NODE);
  hello->set_connector_name(identity.name);
  const std::string nonce = identity.secret.empty() ? std::string() : RandomNonce();
  hello->set_nonce(nonce);
  const TimeNs deadline = MonotonicNowNs() + handshake_timeout_ns;
  CoordinatorMessage in;
  bool authenticated = false;
  // With a secret, the proofs cover the handshake's frames as this end sent and received them.
  if (!identity.secret.empty()) channel.RecordTranscript();
  try {
    channel.Send(out, deadline);
    const std::string hello_sent =
        identity.secret.empty() ? std::string() : channel.TranscriptDigest();
    if (!channel.Receive(&in, deadline, interrupt_fd)) return std::nullopt;
    if (in.has_challenge() && !identity.secret.empty()) {
      // The coordinator proves the secret first: a connector tells nothing to an impostor.
      const proto::coord::Challenge& challenge = in.challenge();
      const std::string hello_and_challenge = channel.TranscriptDigest();
      if (challenge.nonce().size() != kNonceBytes ||
          !SameProof(challenge.proof(), ProofOf(identity.secret, "sitlnet coordinator", nonce,
                                                challenge.nonce() + hello_sent))) {
        throw Error(
            "the coordinator failed to prove the shared secret (a different "
            "--secret-file, or not sitlnet's coordinator)");
      }
      CoordinatorMessage proof;
      proof.mutable_proof()->set_proof(ProofOf(identity.secret, "sitlnet connector",
                                               challenge.nonce(), nonce + hello_and_challenge));
      channel.Send(proof, deadline);
      const SessionKeys keys =
          DeriveSessionKeys(identity.secret, challenge.nonce(), nonce + hello_and_challenge);
      channel.AuthenticateMessages(keys.connector_to_coordinator, keys.coordinator_to_connector);
      authenticated = true;
      if (!channel.Receive(&in, deadline, interrupt_fd)) return std::nullopt;
    }
  } catch (const TransportError& e) {
    throw Error("handshake with the coordinator: " + std::string(e.what()));
  }
  if (in.has_error()) throw Error("the coordinator refused: " + in.error().message());
  if (in.has_challenge()) {
    throw Error(
        "the coordinator asks for a shared secret: give --secret-file (docs/coordinator.md)");
  }
  if (!identity.secret.empty() && !authenticated) {
    throw Error(
        "the coordinator did not authenticate: it has no --secret-file, this connector does");
  }
  if (!in.has_welcome()) {
    throw Error(std::string("handshake with the coordinator: expected Welcome, got ") +
                KindName(in.kind_case()));
  }
  return in.welcome();
}

std::string ServeIterations(Channel& channel, Simulator& simulator, int interrupt_fd) {
  CoordinatorMessage in;
  CoordinatorMessage out;
  for (;;) {
    try {
      if (!channel.Receive(&in, kNoDeadline, interrupt_fd)) return "interrupted";
    } catch (const TransportError& e) {
      throw Error("coordinator connection: " + std::string(e.what()));
    }
    if (in.has_stop()) return in.stop().reason();
    if (in.has_error()) throw Error("the coordinator reported: " + in.error().message());
    if (!in.has_start()) {
      throw Error(std::string("coordinator protocol error: expected Start, got ") +
                  KindName(in.kind_case()));
    }
    const proto::coord::Start& start = in.start();
    out.Clear();
    proto::coord::End* end = out.mutable_end();
    RemoteContext context(channel, start.iteration());
    const TimeNs begin = MonotonicNowNs();
    try {
      simulator.RunIteration(start, end, context);
    } catch (const Error& e) {
      SendErrorQuietly(channel, e.what());
      throw;
    }
    // A simulator that waits for the wall clock within its iteration says how long it worked.
    if (end->busy_ns() == 0) end->set_busy_ns(MonotonicNowNs() - begin);
    end->set_iteration(start.iteration());
    try {
      channel.Send(out);
    } catch (const TransportError& e) {
      throw Error("coordinator connection: sending END: " + std::string(e.what()));
    }
  }
}

}  // namespace sitlnet::coordinator

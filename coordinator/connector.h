// Connectors: how the coordinator drives a simulator (physics or network).
//
// Simulator side: a `Simulator` runs one iteration when asked. Coordinator
// side: a `Connector` sends START and waits for END, either by a direct call
// into a Simulator in this process (InProcessConnector) or over a socket to a
// connector process (RemoteConnector, coordinator/remote_connector.h, served
// there by ServeCoordinator()).
#ifndef SITLNET_COORDINATOR_CONNECTOR_H_
#define SITLNET_COORDINATOR_CONNECTOR_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "common/common.h"
#include "coordinator/transport.h"
#include "sitlnet/coordinator.pb.h"

namespace sitlnet::coordinator {

inline constexpr uint32_t kProtocolVersion = proto::coord::PROTOCOL_VERSION_CURRENT;

// kNode: a node host of a fleet (fleet/fleet.h), which only a fleet's coordinator accepts.
enum class Role { kPhysics, kNetwork, kNode };
std::string RoleName(Role role);  // "physics" / "network" / "node"

//------------------------------ Simulator side ------------------------------

// Lets a simulator report progress inside an iteration.
class IterationContext {
 public:
  virtual ~IterationContext() = default;
  // Physics in lockstep-robots mode: every robot's command for this iteration
  // has arrived; the coordinator may start the network's iteration now.
  virtual void CommandsCollected() = 0;
  // The same, with data for the coordinator (CommandsCollected.payload: a node host's frames).
  // Only a coordinator over a socket receives it; in this process it must be empty.
  virtual void CommandsCollectedWithPayload(std::string payload) {
    SITLNET_DEMAND(payload.empty());
    CommandsCollected();
  }
};

// A simulator the coordinator can step. Implementations: the physics side
// (physics_side/physics_side.h), the network side (network_side/network_side.h)
// and the synthetic ones (synthetic.h: benchmarks, tests).
class Simulator {
 public:
  virtual ~Simulator() = default;
  // Physics: robot poses at virtual time 0. Network: empty.
  virtual proto::coord::Poses InitialPoses() { return {}; }
  // Advances the simulation over [start.start_ns(), start.end_ns()) and fills
  // `end` (physics: poses at end_ns). `end` arrives cleared; iteration and
  // busy_ns are filled by the caller (busy_ns only if the simulator left it 0: one that waits for
  // the wall clock within its iteration sets its own). Throw Error to abort the run.
  virtual void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                            IterationContext& context) = 0;
};

// Runs `simulator` for a coordinator over `channel` until Stop: sends Hello,
// expects Welcome, then answers every Start with End. Returns Stop's reason.
// Throws Error if the coordinator refuses the handshake (its message), sends
// Error, closes the connection, or the simulator throws (then the coordinator
// is told with an Error message first). Returns "interrupted" if
// interrupt_fd fires while waiting for the coordinator.
// It is HandshakeWithCoordinator followed by ServeIterations.
struct ConnectorIdentity {
  std::string name;
  Role role = Role::kPhysics;
  uint64_t scenario_hash = 0;
  // The shared secret (LoadSecretFile); empty: no authentication. With one, the coordinator
  // must prove it holds the same before the connector goes on, and the connector proves it too.
  std::string secret;
};
std::string ServeCoordinator(Channel& channel, Simulator& simulator,
                             const ConnectorIdentity& identity, TimeNs handshake_timeout_ns,
                             int interrupt_fd = -1);

// The first half of ServeCoordinator: sends a Hello of `identity`, with the fields of
// `hello_extra` too (initial poses; a node's robots), and authenticates when identity has a
// secret. Returns the coordinator's Welcome, or nullopt if interrupt_fd fired. Throws Error as
// ServeCoordinator does. A node host handshakes before it creates anything (fleet/).
std::optional<proto::coord::Welcome> HandshakeWithCoordinator(
    Channel& channel, const ConnectorIdentity& identity, const proto::coord::Hello& hello_extra,
    TimeNs handshake_timeout_ns, int interrupt_fd = -1);

// The second half: answers every Start with End until Stop; returns Stop's reason.
std::string ServeIterations(Channel& channel, Simulator& simulator, int interrupt_fd = -1);

// "Start", "CommandsCollected", ...: a message's kind in error lines.
const char* KindName(proto::coord::CoordinatorMessage::KindCase kind);

// A peer-chosen name as messages print it: printable ASCII ('?' for others), 64 bytes at most.
std::string PrintableName(const std::string& name);

// Sends Error(message) within 1 s if the peer still listens; never throws.
void SendErrorQuietly(Channel& channel, const std::string& message);

//----------------------------- Coordinator side -----------------------------

// How long and on what a connector call may wait.
struct WaitLimits {
  TimeNs deadline_ns = kNoDeadline;  // Absolute, CLOCK_MONOTONIC.
  TimeNs timeout_ns = 0;             // The configured timeout, for messages.
  int interrupt_fd = -1;             // Returns false early when readable.
};

// The coordinator's handle on one connector. Errors are thrown as Error whose
// message names the connector and the iteration, e.g. "physics connector
// 'phys0' did not answer START of iteration 42 with END within 5000 ms".
class Connector {
 public:
  // `description`: how messages name it; empty: "<role> connector '<name>'".
  Connector(std::string name, Role role, std::string description = {})
      : name_(std::move(name)), role_(role), description_(std::move(description)) {}
  virtual ~Connector() = default;
  const std::string& name() const { return name_; }
  Role role() const { return role_; }
  // "physics connector 'phys0'", or the description given.
  std::string Describe() const;

  virtual const proto::coord::Poses& initial_poses() const = 0;
  // Sends START (returns without waiting for the iteration).
  virtual void Begin(const proto::coord::Start& start, const WaitLimits& limits) = 0;
  // Waits for CommandsCollected of `iteration`; false if interrupted.
  virtual bool AwaitCommandsCollected(uint64_t iteration, const WaitLimits& limits) = 0;
  // Waits for END of `iteration` into `end`; false if interrupted.
  virtual bool Finish(uint64_t iteration, proto::coord::End* end, const WaitLimits& limits) = 0;
  // True if Finish() does the work on the caller's thread: the coordinator
  // then calls it before waiting for the others, so they overlap.
  virtual bool runs_on_caller_thread() const { return false; }
  // Tells the connector the run is over (best effort, never throws).
  virtual void Stop(const std::string& reason) = 0;

 private:
  std::string name_;
  Role role_;
  std::string description_;
};

// Calls a Simulator in this process. kOwnThread runs it on a worker thread so
// physics and network overlap; kCallerThread runs it inside Finish() on the
// caller's thread (no hand-off; cannot be used for lockstep-robots physics).
// Run the slower simulator on the caller's thread: the coordinator then never
// sleeps waiting for it. `spin_ns` (kOwnThread): how long the worker and the
// waiting coordinator spin before sleeping (0: sleep at once; spinning was
// measured to hurt on 2 shared cores, docs/performance.md). A simulator stuck
// past the timeout is reported like a remote one, but destroying its
// connector waits for it to return (its thread cannot be abandoned safely).
enum class Threading { kOwnThread, kCallerThread };
std::unique_ptr<Connector> MakeInProcessConnector(std::string name, Role role, Simulator* simulator,
                                                  Threading threading, TimeNs spin_ns = 0);

// What the coordinator demands of a connecting connector.
struct HandshakeExpectation {
  uint64_t scenario_hash = 0;
  TimeNs iteration_ns = 0;
  bool lockstep_robots = false;
  // If set, a connector of the other role is refused with an Error naming
  // both roles (a coordinator that waits for one remote side only).
  std::optional<Role> role;
  // The shared secret (LoadSecretFile); empty: none. With one, a connector that does not prove
  // it holds the same secret is a stray connection: sent Error, not accepted, not fatal.
  std::string secret;
  // Checked last, before Welcome, on the handshake's own thread: a non-empty line refuses the
  // peer as another scenario would (a fleet's node with robots not its own). May be empty.
  std::function<std::string(const proto::coord::Hello&)> refuse_hello = {};
};

// A peer that completed the handshake: Welcome was sent on `channel`.
struct AcceptedPeer {
  Channel channel;
  proto::coord::Hello hello;
  Role role = Role::kPhysics;
  // PrintableName(hello.connector_name()).
  std::string name;
};

// Accepts connections on `listener` until one physics and one network
// connector completed the handshake. A connector with another protocol
// version or scenario hash, or a second one of a role, is sent Error and the
// call throws Error naming it. Times out (Error) at limits.deadline_ns.
struct AcceptedConnectors {
  std::unique_ptr<Connector> physics;
  std::unique_ptr<Connector> network;
};
// `spin_ns`: see Channel::set_spin_ns.
AcceptedConnectors AcceptConnectors(Listener& listener, const HandshakeExpectation& expect,
                                    const WaitLimits& limits, FrameCodecOptions codec = {},
                                    TimeNs spin_ns = 0);

// A connection that is not a connector: closed, silent for 2 s, or sending
// anything but a Hello (a port scanner, a stray client). AcceptConnectors
// logs it and keeps waiting; a real connector with another scenario or
// protocol version is an Error instead (a misconfiguration to fix).
class StrayConnectionError : public Error {
 public:
  using Error::Error;
};

// Handshake on an already-accepted channel (AcceptConnectors uses it). Returns
// nullopt if interrupted. Refuses a node unless expect.role is kNode. Throws
// StrayConnectionError or, for a refused peer, Error (after sending it Error).
std::optional<AcceptedPeer> AcceptPeer(Channel channel, const HandshakeExpectation& expect,
                                       const WaitLimits& limits);
// AcceptPeer, then a RemoteConnector over the channel; null if interrupted.
std::unique_ptr<Connector> AcceptConnector(Channel channel, const HandshakeExpectation& expect,
                                           const WaitLimits& limits);

// Accepts connections on `listener`, their handshakes (AcceptPeer) side by side, at most 16 at
// once, and hands each accepted peer to `take` until it returns true. Stray connections are
// logged and skipped. Returns false if limits.interrupt_fd fired; throws a handshake's refusal
// or what `take` throws. At limits.deadline_ns throws Error "<missing()> to <endpoint> within
// <timeout> ms", e.g. missing() = "no physics connector connected".
bool AcceptUntil(Listener& listener, const HandshakeExpectation& expect, const WaitLimits& limits,
                 const std::function<bool(AcceptedPeer)>& take,
                 const std::function<std::string()>& missing, FrameCodecOptions codec = {},
                 TimeNs spin_ns = 0);

// Accepts connections on `listener` until one connector of `role` completed
// the handshake (stray connections are logged and skipped, as above). Throws
// Error "no network connector connected to tcp:0.0.0.0:7100 within 60000 ms"
// at limits.deadline_ns, or the handshake's refusal. Returns null if
// interrupted. Used by `sitlnet run --remote network`.
std::unique_ptr<Connector> AcceptConnectorOfRole(Listener& listener, Role role,
                                                 HandshakeExpectation expect,
                                                 const WaitLimits& limits);

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_CONNECTOR_H_

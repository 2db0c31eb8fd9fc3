// One robot's link to its software in one protocol (docs/protocols.md): the native protobuf
// protocol, ArduPilot's JSON, PX4's simulator MAVLink. PhysicsServer holds a list of links and
// names no protocol: it polls them, steps the world to the next step one of them is due at,
// has them serve, and (pacing) waits for the answers they say are outstanding. A new protocol
// is one new file with its Make...Link, listed in MakeRobotLinks (robot_link.cc).
#ifndef SITLNET_PHYSICS_MUJOCO_ROBOT_LINK_H_
#define SITLNET_PHYSICS_MUJOCO_ROBOT_LINK_H_

#include <netinet/in.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "physics_mujoco/answer_meter.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/udp_socket.h"

namespace sitlnet::physics {

// What a robot's links share: its place in the world, its membership of the lock-step and its
// public counters. Owned by the server, one per robot.
struct RobotLinkContext {
  World* world = nullptr;
  int robot = 0;
  // Out of the lock-step (on_silent_robot drop): motors cut, commands and frames refused,
  // until the robot's software starts over (Rejoin).
  bool dropped = false;
  bool motors_cut = false;  // The motors were cut (failsafe, drop) and no command came since.
  RobotCounters counters;
  AnswerMeter answers;  // Its autopilot's answers in wall time (an autopilot link counts them).

  // The robot's software started over (a restarted autopilot): it is in the lock-step again.
  void Rejoin() {
    dropped = false;
    motors_cut = false;
  }
  // Sends a datagram, counting a refusal in counters.send_errors.
  void Send(const UdpSocket& socket, const std::string& bytes, const sockaddr_in& to) {
    if (!socket.SendTo(bytes.data(), bytes.size(), to)) ++counters.send_errors;
  }
};

class RobotLink;

// What a link's builder gets: the robot, where its sockets go, the server's wiring.
struct RobotLinkSetup {
  const Scenario* scenario = nullptr;
  const RobotPlan* plan = nullptr;
  RobotLinkContext* robot = nullptr;  // Shared by the robot's links; outlives them.
  std::string who;                    // "<scenario>: robot \"name\"", for errors.
  // Adds a link's fd to the server's epoll set: the link's Poll() is called when it becomes
  // readable. A link may call it again later (a new connection); a closed fd leaves the set.
  std::function<void(RobotLink* link, int fd)> watch;
  bool periodic_states = true;  // ServerOptions::periodic_states.
};

// What a silent autopilot did not answer, in its protocol's words: "robot 'a' did not answer
// <unanswered> ... <expected> within ...".
struct UnansweredMessage {
  const char* unanswered = "";
  const char* expected = "";
};

class RobotLink {
 public:
  virtual ~RobotLink() = default;

  // Handles what has arrived on the link's sockets (non-blocking, bounded per call).
  virtual void Poll() = 0;
  // Handles what has arrived on `fd`, one of the fds the link watches (the server's epoll said
  // it is readable). A link with several fds reads only that one: no system call on the others.
  virtual void PollReadable(int /*fd*/) { Poll(); }
  // Physics steps from the world's current time until the link next has something to send or
  // to do (>= 1; INT_MAX: nothing scheduled). The server never steps past it.
  virtual int StepsUntilDue() const = 0;
  // Sends what is due at the world's current time and applies the link's own timeouts.
  virtual void Serve() = 0;
  // The robot's software has made itself known (a command, a frame, a connection).
  virtual bool spoke() const = 0;
  // The robot was dropped from the lock-step (the context says so already): stop serving it.
  virtual void OnDropped() {}

  // -- The robot lock-step (native protocol; docs/protocols.md, "lock-step"): one state per
  // iteration, answered by one command before the iteration's physics.
  // Sends the iteration's state if the robot is in the lock-step.
  virtual void SendLockstepState() {}
  // The robot is in the lock-step and has not answered the last state yet.
  virtual bool LockstepCommandMissing() const { return false; }

  // -- Autopilots paced by the server (ArduPilot JSON, PX4): the frame gate (lockstep) and the
  // wall-clock hold (realtime) wait for their answers inside an iteration.
  // True for an autopilot link: its messages due at an iteration's end leave at the next
  // iteration's start (frame gate), and on the wall clock (realtime hold).
  virtual bool paced() const { return false; }
  // A message is due at the world's current time (it leaves at that time's wall instant).
  virtual bool DueNow() const { return false; }
  // The software owes an answer to the last message sent (the robot not dropped).
  virtual bool AnswerOutstanding() const { return false; }
  // What a silent autopilot of this protocol did not answer.
  virtual UnansweredMessage unanswered() const { return {}; }
  // Fills the PX4 counters of a PX4 link (others leave it empty).
  virtual void ReportPx4(std::optional<Px4Counters>* /*counters*/) const {}

  // The frame gate's silent-autopilot policy: an autopilot that missed the gate's timeout is
  // reported once and not waited for again until it answers (each protocol says when: Unmute).
  bool Awaited() const { return AnswerOutstanding() && !muted_; }
  void Mute() { muted_ = true; }

  // The robot, and the position of the link's protocol in MakeRobotLinks' list (silent
  // autopilots are reported in that order). Set by MakeRobotLinks.
  int robot = 0;
  int kind = 0;

 protected:
  void Unmute() { muted_ = false; }

 private:
  bool muted_ = false;
};

// The links of one robot, in protocol order (native, ArduPilot JSON, PX4): one per protocol the
// robot's spec asks for. Throws Error naming the robot for a bad setting or a socket that cannot
// be bound.
std::vector<std::unique_ptr<RobotLink>> MakeRobotLinks(const RobotLinkSetup& setup);

// One per protocol (native_link.cc, ardupilot_json_link.cc, px4_link.cc); null when the robot's
// spec does not ask for it.
std::unique_ptr<RobotLink> MakeNativeLink(const RobotLinkSetup& setup);
std::unique_ptr<RobotLink> MakeArduPilotJsonLink(const RobotLinkSetup& setup);
std::unique_ptr<RobotLink> MakePx4Link(const RobotLinkSetup& setup);

// Larger than any valid MotorCommand or servo packet; a bigger datagram is malformed.
inline constexpr size_t kReceiveBufferBytes = 2048;

// Receives up to a budget of datagrams on `socket`, calling handle(data, size, from) for each
// (size > kReceiveBufferBytes: the datagram was truncated), in arrival order.
// Batched: one recvmmsg takes what is waiting, so a datagram costs one system call, not a
// receive and a last one that finds nothing (docs/performance.md, "The harness's share per
// autopilot step"). A batch that is not full means the socket was empty; what comes after stays
// readable (level-triggered epoll) for the next Poll.
// Bounded: a robot flooding its socket cannot stall the others or the stepping.
template <typename Handler>
void DrainDatagrams(const UdpSocket& socket, Handler handle) {
  constexpr int kDrainBudget = 256;  // Datagrams per socket per Poll.
  constexpr int kBatch = 8;          // An autopilot sends one frame a step; a robot a few.
  uint8_t buffers[kBatch][kReceiveBufferBytes];
  DatagramSlot slots[kBatch];
  for (int i = 0; i < kBatch; ++i) slots[i] = {buffers[i], sizeof buffers[i], 0, {}};
  for (int budget = kDrainBudget; budget > 0; budget -= kBatch) {
    const int n = socket.ReceiveBatch(slots, kBatch);
    for (int i = 0; i < n; ++i) handle(slots[i].data, slots[i].length, slots[i].from);
    if (n < kBatch) return;
  }
}

// Whole physics steps from `now_ns` to `due_ns`, rounded up, clamped to [1, INT_MAX].
int StepsUntil(TimeNs due_ns, TimeNs now_ns, TimeNs step_ns);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_ROBOT_LINK_H_

// PhysicsServer: the World plus every robot's UDP endpoints (docs/protocols.md).
#include <poll.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "clock/clock.h"
#include "physics_mujoco/ardupilot_json.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/px4_robot.h"
#include "physics_mujoco/robot_codec.h"
#include "physics_mujoco/udp_socket.h"

namespace sitlnet::physics {
namespace {

// Larger than any valid MotorCommand or servo packet; a bigger datagram is malformed.
constexpr size_t kReceiveBufferBytes = 2048;
// Datagrams handled per socket per Poll.
constexpr int kDrainBudget = 256;

struct Endpoint {
  int robot = 0;
  Ipv4 robot_address;
  UdpSocket native;
  UdpSocket json;  // fd -1 when the robot has no ArduPilot endpoint
  double max_speed_rad_s = 0;
  // Native protocol.
  bool subscribed = false;
  sockaddr_in reply{};
  bool has_command = false;
  bool motors_cut = false;
  TimeNs last_command_ns = 0;
  uint64_t command_step = 0;
  // Lock-step: a command arrived since the last SendStates(). An announce sent
  // before the state (with the same step number) must not count as its answer.
  bool answered_state = false;
  // Dropped from the lock-step (silent too long, scenario policy): motors cut,
  // commands ignored, no more states.
  bool dropped = false;
  TimeNs state_period_ns = 0;
  TimeNs next_state_ns = 0;
  TimeNs timeout_ns = 0;  // 0: failsafe off
  // ArduPilot JSON (docs/protocols.md): a frame asks for the state at its end; the reply waits
  // until the world's clock has reached that time.
  FrameTracker tracker;
  std::string last_json;
  sockaddr_in json_reply{};
  uint16_t json_rate_hz = 0;
  int64_t json_base_steps = 0;
  int64_t json_frames = 0;
  bool json_joined = false;   // Sent a frame: the frame gate waits for its next one.
  bool json_pending = false;  // A frame's reply is due at json_due_steps.
  int64_t json_due_steps = 0;
  // Missed the frame gate's timeout: not waited for again until it sends a frame.
  bool json_silent = false;
  // PX4 simulator interface (docs/autopilots.md); null when the robot has none.
  std::unique_ptr<Px4Robot> px4;
  // The link's connection in the epoll set, by its number among the link's connections: a new
  // connection can reuse the closed one's fd number (and a closed fd leaves the set by itself).
  uint64_t px4_watched_connection = 0;
  bool px4_silent = false;  // As json_silent.
  RobotCounters counters;
};

}  // namespace

struct PhysicsServer::Impl {
  const Scenario& scenario;
  World world;
  std::vector<Endpoint> endpoints;
  int epoll_fd = -1;
  proto::RobotState state;  // reused buffers
  std::string wire;
  std::vector<float> lidar;

  std::optional<GeodeticFrame> geodetic;  // For PX4 robots' GPS.

  Impl(const Scenario& s, const ServerOptions& options) : scenario(s), world(s, options.world) {}
  ~Impl() {
    if (epoll_fd >= 0) close(epoll_fd);
  }

  void Watch(int fd, uint64_t key) {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.u64 = key;
    if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event) != 0) {
      throw Error(SystemErrorMessage("physics server: epoll_ctl", errno));
    }
  }

  void HandleNative(Endpoint& ep, const uint8_t* data, ssize_t size, const sockaddr_in& from) {
    if (SockaddrIpv4(from) != ep.robot_address) {
      ++ep.counters.dropped_foreign_source;
      return;
    }
    DecodedCommand command;
    const CommandVerdict verdict =
        size > static_cast<ssize_t>(kReceiveBufferBytes)
            ? CommandVerdict::kMalformed
            : DecodeMotorCommand(data, size, ep.robot, ep.max_speed_rad_s, &command);
    switch (verdict) {
      case CommandVerdict::kMalformed:
        ++ep.counters.dropped_malformed;
        return;
      case CommandVerdict::kInvalid:
        ++ep.counters.dropped_invalid;
        return;
      case CommandVerdict::kWrongRobot:
        ++ep.counters.dropped_wrong_robot;
        return;
      case CommandVerdict::kAccepted:
        break;
    }
    if (ep.dropped) {
      // Out of the lock-step for good: its motors stay cut (docs/physics.md).
      ++ep.counters.dropped_after_drop;
      return;
    }
    ++ep.counters.commands_accepted;
    world.SetRotorTarget(ep.robot, command.target_rad_s);
    ep.has_command = true;
    ep.motors_cut = false;
    ep.last_command_ns = world.time_ns(ep.robot);
    ep.command_step = command.step;
    ep.answered_state = true;
    ep.reply = from;
    ep.subscribed = true;
  }

  void HandleJson(Endpoint& ep, const uint8_t* data, ssize_t size, const sockaddr_in& from) {
    const auto packet = size <= static_cast<ssize_t>(kReceiveBufferBytes)
                            ? ParseServoPacket(data, size)
                            : std::nullopt;
    if (SockaddrIpv4(from) != ep.robot_address || !packet) {
      ++ep.counters.json_dropped;
      return;
    }
    uint64_t missed = 0;
    const FrameAction action = ep.tracker.OnFrame(packet->frame_count, &missed);
    if (action == FrameAction::kResend) {
      // SITL repeats a frame whose reply it has not seen: the reply already sent goes again; one
      // not yet due will go when it is.
      ++ep.counters.json_resends;
      if (!ep.json_pending && !ep.last_json.empty()) Send(ep, ep.json, ep.last_json, from);
      return;
    }
    if (action == FrameAction::kRestart) {
      // SITL restarted: the vehicle starts over where it began, at the world's current time,
      // and the robot rejoins the lock-step if it had been dropped.
      ++ep.counters.json_restarts;
      world.ResetRobot(ep.robot);
      ep.json_rate_hz = 0;
      ep.dropped = false;
      ep.motors_cut = false;
    }
    if (ep.dropped) {
      ++ep.counters.dropped_after_drop;
      return;
    }
    ++ep.counters.json_frames;
    ep.counters.json_missed_frames += missed;
    world.SetRotorTarget(ep.robot, PwmToRotorSpeeds(*packet, ep.max_speed_rad_s));
    const int64_t now_steps = world.steps(ep.robot);
    if (packet->frame_rate_hz != ep.json_rate_hz) {  // new rate: count frames from here
      ep.json_rate_hz = packet->frame_rate_hz;
      ep.json_base_steps = now_steps;
      ep.json_frames = 0;
    }
    ++ep.json_frames;
    // Frame n ends at n / frame_rate: whole physics steps, the remainder carried (exact over
    // many frames when 1/frame_rate is not a multiple of the step).
    int64_t due_steps =
        ep.json_base_steps + clock::TickTimeNs(ep.json_frames, ep.json_rate_hz) / world.step_ns();
    if (due_steps < now_steps) {
      // Late (realtime pacing, SITL slower than the clock): frames count from now on.
      ep.json_base_steps += now_steps - due_steps;
      due_steps = now_steps;
    }
    ep.json_due_steps = due_steps;
    ep.json_pending = true;
    ep.json_joined = true;
    ep.json_silent = false;
    ep.json_reply = from;
    ReplyJsonIfDue(ep);
  }

  // Sends the state of a pending frame once the world's clock has reached the frame's end.
  void ReplyJsonIfDue(Endpoint& ep) {
    if (!ep.json_pending || world.steps(ep.robot) < ep.json_due_steps) return;
    ep.json_pending = false;
    ep.last_json =
        FormatJsonState(world.time_ns(ep.robot), world.Pose(ep.robot), world.Imu(ep.robot));
    Send(ep, ep.json, ep.last_json, ep.json_reply);
  }

  // The frame gate (lockstep pacing): before the clock moves on, every autopilot that has
  // joined (and is not dropped) must have answered its last message: an ArduPilot robot with
  // the frame answering its last reply, a PX4 robot in lock-step with the motor outputs
  // answering its last HIL_SENSOR. Waits up to frame_gate_timeout_ns of wall time; robots still
  // silent then are recorded for the caller's policy and not waited for again until they answer.
  // An answer is outstanding: an ArduPilot frame for its last reply, PX4's controls for its last
  // HIL_SENSOR (the robot not dropped). The frame gate waits only for those not reported silent.
  static bool JsonAnswerOutstanding(const Endpoint& ep) {
    return ep.json.fd() >= 0 && ep.json_joined && !ep.json_pending && !ep.dropped;
  }
  static bool Px4AnswerOutstanding(const Endpoint& ep) {
    return ep.px4 && !ep.dropped && ep.px4->link().awaiting_answer();
  }
  bool AwaitedJson(const Endpoint& ep) const {
    return JsonAnswerOutstanding(ep) && !ep.json_silent;
  }
  bool AwaitedPx4(const Endpoint& ep) const { return Px4AnswerOutstanding(ep) && !ep.px4_silent; }
  // Polls until no endpoint satisfies `waiting_for` (true) or the wall clock reaches
  // `deadline_ns` (false).
  template <typename Predicate>
  bool AwaitAnswers(TimeNs deadline_ns, Predicate waiting_for) {
    for (;;) {
      if (std::none_of(endpoints.begin(), endpoints.end(), waiting_for)) return true;
      const TimeNs left_ns = deadline_ns - MonotonicNowNs();
      if (left_ns <= 0) return false;
      pollfd fd{epoll_fd, POLLIN, 0};
      const timespec wait{static_cast<time_t>(left_ns / kNsPerS),
                          static_cast<long>(left_ns % kNsPerS)};
      ppoll(&fd, 1, &wait, nullptr);
      Poll();
    }
  }
  void WaitForAutopilots() {
    const auto waiting_for = [this](const Endpoint& ep) {
      return AwaitedJson(ep) || AwaitedPx4(ep);
    };
    if (AwaitAnswers(MonotonicNowNs() + frame_gate_timeout_ns, waiting_for)) return;
    for (Endpoint& ep : endpoints) {
      if (!waiting_for(ep)) continue;  // Answered, or reported silent before.
      if (AwaitedJson(ep)) ep.json_silent = true;
      if (AwaitedPx4(ep)) ep.px4_silent = true;
      silent_robots.push_back(ep.robot);
    }
  }

  // Realtime hold: the world does not run ahead of the wall clock while an autopilot's answer
  // (an ArduPilot frame, PX4's controls) is awaited; it waits for the answer up to the wall
  // instant of its next step. False if some answer has not come by then.
  bool AwaitAnswersOnWallClock() {
    return AwaitAnswers(
        realtime->WallOf(world.time_ns(0) + world.step_ns()),
        [](const Endpoint& ep) { return JsonAnswerOutstanding(ep) || Px4AnswerOutstanding(ep); });
  }

  // Takes what PX4 sent: a new connection (PX4 restarted: the robot is back at its start and
  // rejoins the lock-step), its latest motor outputs (ignored while the robot is dropped).
  void PollPx4(Endpoint& ep) {
    if (ep.px4->PollLink(&world)) {
      ep.dropped = false;
      ep.motors_cut = false;
      ep.px4_silent = false;
    }
    const Px4SimulatorLink& link = ep.px4->link();
    if (link.connection_fd() >= 0 && link.counters().connections != ep.px4_watched_connection) {
      ep.px4_watched_connection = link.counters().connections;
      Watch(link.connection_fd(), 2 * endpoints.size() + ep.robot);
    }
    if (link.answered_last_sensor()) ep.px4_silent = false;  // Answering again.
    if (!ep.dropped) world.SetRotorTarget(ep.robot, link.command().rotor_speeds_rad_s);
  }

  // Sends a PX4 robot's sensor messages when due (at the world's current time).
  void SendPx4SensorsIfDue(Endpoint& ep) {
    if (ep.px4) ep.px4->Step(&world, world.time_ns(ep.robot));
  }

  // What an autopilot is due at the world's current time: an ArduPilot reply, PX4's sensors.
  void ServeAutopilot(Endpoint& ep) {
    ReplyJsonIfDue(ep);
    SendPx4SensorsIfDue(ep);
  }

  int StepsUntilPx4Sensor(const Endpoint& ep) const {
    if (!ep.px4 || !ep.px4->link().connected()) return std::numeric_limits<int>::max();
    const TimeNs step = world.step_ns();
    const TimeNs left = ep.px4->next_sensor_ns() - world.time_ns(ep.robot);
    return static_cast<int>(
        std::clamp<TimeNs>((left + step - 1) / step, 1, std::numeric_limits<int>::max()));
  }

  int StepsUntilJsonReply(const Endpoint& ep) const {
    if (!ep.json_pending) return std::numeric_limits<int>::max();
    return static_cast<int>(std::clamp<int64_t>(ep.json_due_steps - world.steps(ep.robot), 1,
                                                std::numeric_limits<int>::max()));
  }

  void Send(Endpoint& ep, const UdpSocket& sock, const std::string& bytes, const sockaddr_in& to) {
    if (!sock.SendTo(bytes.data(), bytes.size(), to)) ++ep.counters.send_errors;
  }

  void Drain(Endpoint& ep, bool json) {
    uint8_t buffer[kReceiveBufferBytes];
    sockaddr_in from{};
    const UdpSocket& sock = json ? ep.json : ep.native;
    // Bounded: a robot flooding its socket cannot stall the others or the stepping; what is
    // left stays readable (level-triggered epoll) for the next Poll.
    int budget = kDrainBudget;
    for (ssize_t n; budget-- > 0 && (n = sock.Receive(buffer, sizeof buffer, &from)) >= 0;) {
      if (json) {
        HandleJson(ep, buffer, n, from);
      } else {
        HandleNative(ep, buffer, n, from);
      }
    }
  }

  void Poll() {
    epoll_event events[64];
    // Enough rounds to see every socket once (epoll rotates its ready list), no more: a
    // sustained flood cannot keep Poll from returning.
    const size_t rounds = 1 + 2 * endpoints.size() / 64;
    for (size_t round = 0; round < rounds; ++round) {
      const int n = epoll_wait(epoll_fd, events, 64, 0);
      if (n <= 0) return;
      for (int i = 0; i < n; ++i) {
        const uint64_t key = events[i].data.u64;
        if (key >= 2 * endpoints.size()) {
          PollPx4(endpoints[key - 2 * endpoints.size()]);
        } else {
          Drain(endpoints[key / 2], key % 2 == 1);
        }
      }
      if (n < 64) return;
    }
  }

  int StepsUntilEvent(const Endpoint& ep) const {
    const TimeNs now = world.time_ns(ep.robot);
    TimeNs next = ep.next_state_ns;
    if (ep.has_command && !ep.motors_cut && ep.timeout_ns > 0) {
      next = std::min(next, ep.last_command_ns + ep.timeout_ns);
    }
    const TimeNs step = world.step_ns();
    return static_cast<int>(std::max<TimeNs>(1, (next - now + step - 1) / step));
  }

  void Service(Endpoint& ep) {
    const TimeNs now = world.time_ns(ep.robot);
    if (ep.has_command && !ep.motors_cut && ep.timeout_ns > 0 &&
        now - ep.last_command_ns >= ep.timeout_ns) {
      world.SetRotorTarget(ep.robot, RotorSpeeds{});  // ESC failsafe: motors spin down
      ep.motors_cut = true;
      ++ep.counters.failsafe_cuts;
    }
    if (now < ep.next_state_ns) return;
    while (ep.next_state_ns <= now) ep.next_state_ns += ep.state_period_ns;
    if (ep.subscribed && periodic_states) SendState(ep);
  }

  void SendState(Endpoint& ep) {
    world.Lidar(ep.robot, &lidar);
    FillRobotState(ep.robot, world.steps(ep.robot), world.time_ns(ep.robot), world.Pose(ep.robot),
                   world.Imu(ep.robot), lidar, world.rotor_speeds(ep.robot), ep.command_step,
                   ep.motors_cut, &state);
    state.SerializeToString(&wire);
    Send(ep, ep.native, wire, ep.reply);
    ++ep.counters.states_sent;
  }

  bool periodic_states = true;

  bool InLockStep(const Endpoint& ep) const { return ep.subscribed && !ep.dropped; }

  std::vector<int> CollectCommands(TimeNs timeout_ns) {
    const TimeNs deadline_ns = MonotonicNowNs() + timeout_ns;
    std::vector<int> missing;
    for (;;) {
      Poll();
      missing.clear();
      for (const Endpoint& ep : endpoints) {
        if (InLockStep(ep) && (!ep.answered_state ||
                               ep.command_step != static_cast<uint64_t>(world.steps(ep.robot)))) {
          missing.push_back(ep.robot);
        }
      }
      const TimeNs left_ns = deadline_ns - MonotonicNowNs();
      if (missing.empty() || left_ns <= 0) return missing;
      pollfd fd{epoll_fd, POLLIN, 0};
      const timespec wait{static_cast<time_t>(left_ns / kNsPerS),
                          static_cast<long>(left_ns % kNsPerS)};
      ppoll(&fd, 1, &wait, nullptr);
    }
  }

  // What an autopilot is due now (a reply, PX4's sensors).
  bool AutopilotDue(const Endpoint& ep) const {
    const bool json = ep.json_pending && world.steps(ep.robot) >= ep.json_due_steps;
    const bool px4 =
        ep.px4 && ep.px4->link().connected() && world.time_ns(ep.robot) >= ep.px4->next_sensor_ns();
    return json || px4;
  }

  // Realtime pacing: what autopilots are due now leaves at the wall instant of the world's
  // virtual time, not earlier (the physics computes an iteration ahead of the wall clock).
  void HoldForWallClock() {
    if (realtime == nullptr || world.robot_count() == 0) return;
    if (std::none_of(endpoints.begin(), endpoints.end(),
                     [this](const Endpoint& ep) { return AutopilotDue(ep); })) {
      return;
    }
    // The coordinator's timebase is on CLOCK_MONOTONIC (clock::SystemWallClock), as here.
    const TimeNs wall_ns = realtime->WallOf(world.time_ns(0));
    if (wall_ns > MonotonicNowNs()) clock::SystemWallClock().SleepUntilNs(wall_ns);
  }

  void Advance(int steps) {
    Poll();
    // With the frame gate (lockstep), a reply due at the end of the previous Advance leaves now,
    // at the start of this one: what the autopilot does in answer (its next frame, its radio
    // traffic) then falls in this iteration, whose network part drains its TAP after physics,
    // instead of racing the previous iteration's.
    HoldForWallClock();
    for (Endpoint& ep : endpoints) ServeAutopilot(ep);
    for (int remaining = steps; remaining > 0;) {
      int chunk = remaining;
      if (frame_gate_timeout_ns > 0) {
        WaitForAutopilots();
      } else if (realtime != nullptr && world.robot_count() > 0 && !AwaitAnswersOnWallClock()) {
        chunk = 1;  // Not answered yet: the world follows the wall clock a step at a time.
      }
      for (const Endpoint& ep : endpoints) {
        chunk = std::min(
            {chunk, StepsUntilEvent(ep), StepsUntilJsonReply(ep), StepsUntilPx4Sensor(ep)});
      }
      world.Advance(chunk);
      remaining -= chunk;
      const bool defer_replies = remaining == 0 && frame_gate_timeout_ns > 0;
      if (!defer_replies) HoldForWallClock();
      for (Endpoint& ep : endpoints) {
        Service(ep);
        if (!defer_replies) ServeAutopilot(ep);
      }
    }
  }

  TimeNs frame_gate_timeout_ns = 0;           // 0: the clock never waits for ArduPilot frames
  const clock::Timebase* realtime = nullptr;  // Set: autopilots are served on the wall clock.
  std::vector<int> silent_robots;
  bool has_autopilots = false;  // ArduPilot or PX4 robots: the frame gate applies
};

PhysicsServer::PhysicsServer(const Scenario& scenario, const ServerOptions& options)
    : impl_(std::make_unique<Impl>(scenario, options)) {
  impl_->epoll_fd = epoll_create1(EPOLL_CLOEXEC);
  if (impl_->epoll_fd < 0) throw Error(SystemErrorMessage("physics server: epoll_create1", errno));
  const uint32_t port = scenario.spec.addresses().physics_port();
  impl_->endpoints.resize(scenario.robots.size());
  const auto make_sockets = [&] {
    for (const RobotPlan& plan : scenario.robots) {
      const std::string who = scenario.source_path + ": robot \"" + plan.name + "\"";
      const proto::Robot& spec = plan.spec;
      if (!(std::isfinite(spec.state_rate_hz()) && spec.state_rate_hz() > 0)) {
        throw Error(who + ": state_rate_hz must be > 0");
      }
      if (spec.command_timeout_ms() < 0) throw Error(who + ": command_timeout_ms must be >= 0");
      if (spec.ardupilot_json_port() > 65535 || spec.ardupilot_json_port() == port) {
        throw Error(who +
                    ": ardupilot_json_port must be in [1, 65535] and differ from physics_port");
      }
      Endpoint& ep = impl_->endpoints[plan.index];
      ep.robot = plan.index;
      ep.robot_address = plan.ctl_robot_address;
      ep.max_speed_rad_s = plan.airframe.max_rotor_speed_rad_s();
      ep.state_period_ns =
          std::max<TimeNs>(1, std::llround(static_cast<double>(kNsPerS) / spec.state_rate_hz()));
      ep.next_state_ns = ep.state_period_ns;
      ep.timeout_ns = spec.command_timeout_ms() * kNsPerMs;
      ep.native = UdpSocket::Bind(plan.ctl_root_address, static_cast<uint16_t>(port), true, who);
      impl_->Watch(ep.native.fd(), 2 * uint64_t(plan.index));
      if (spec.px4_sim_port() != 0) {
        if (spec.px4_sim_port() > 65535 || spec.px4_sim_port() == port ||
            spec.px4_sim_port() == spec.ardupilot_json_port()) {
          throw Error(who + ": px4_sim_port must be in [1, 65535] and differ from physics_port");
        }
        if (!impl_->geodetic) impl_->geodetic.emplace(scenario.spec.geodetic_origin());
        ep.px4 = std::make_unique<Px4Robot>(
            scenario, plan.index, static_cast<uint16_t>(spec.px4_sim_port()), &*impl_->geodetic);
        impl_->Watch(ep.px4->link().listen_fd(), 2 * scenario.robots.size() + plan.index);
        impl_->has_autopilots = true;
      }
      if (spec.ardupilot_json_port() != 0) {
        ep.json = UdpSocket::Bind(plan.ctl_root_address,
                                  static_cast<uint16_t>(spec.ardupilot_json_port()), true,
                                  who + " (ArduPilot JSON)");
        impl_->Watch(ep.json.fd(), 2 * uint64_t(plan.index) + 1);
        impl_->has_autopilots = true;
      }
    }
  };
  if (options.make_sockets) {
    options.make_sockets(make_sockets);
  } else {
    make_sockets();
  }
}

PhysicsServer::~PhysicsServer() = default;

void PhysicsServer::Poll() { impl_->Poll(); }
void PhysicsServer::SetPeriodicStates(bool enabled) { impl_->periodic_states = enabled; }
void PhysicsServer::DropFromLockstep(int robot) {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->endpoints.size()));
  auto& ep = impl_->endpoints[robot];
  if (ep.dropped) return;
  ep.dropped = true;
  ep.motors_cut = true;
  ep.json_pending = false;  // An ArduPilot robot gets no more replies until SITL restarts.
  impl_->world.SetRotorTarget(robot, RotorSpeeds{});  // as an ESC failsafe: spin down
  ++ep.counters.failsafe_cuts;
}
void PhysicsServer::SendStates() {
  for (Endpoint& ep : impl_->endpoints) {
    if (impl_->InLockStep(ep)) {
      ep.answered_state = false;
      impl_->SendState(ep);
    }
  }
}
std::vector<int> PhysicsServer::CollectCommands(TimeNs timeout_ns) {
  return impl_->CollectCommands(timeout_ns);
}
void PhysicsServer::Advance(int steps) { impl_->Advance(steps); }
void PhysicsServer::SetFrameGate(TimeNs timeout_ns) {
  impl_->frame_gate_timeout_ns = std::max<TimeNs>(0, timeout_ns);
}
bool PhysicsServer::has_frame_gated_robots() const { return impl_->has_autopilots; }
void PhysicsServer::HoldAutopilotsToWallClock(const clock::Timebase* timebase) {
  impl_->realtime = timebase;
}
bool PhysicsServer::spoke(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->endpoints.size()));
  const auto& ep = impl_->endpoints[robot];
  return ep.counters.commands_accepted > 0 || ep.counters.json_frames > 0 ||
         (ep.px4 && ep.px4->link().counters().connections > 0);
}
std::optional<Px4Counters> PhysicsServer::px4_counters(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->endpoints.size()));
  const auto& ep = impl_->endpoints[robot];
  if (!ep.px4) return std::nullopt;
  const Px4LinkCounters& link = ep.px4->link().counters();
  const mavlink::ParserCounters& parser = link.parser;
  Px4Counters counters;
  counters.connections = link.connections;
  counters.reconnections = link.reconnections;
  counters.sensors_sent = link.sensors_sent;
  counters.gps_sent = link.gps_sent;
  counters.actuator_controls = link.actuator_controls;
  counters.heartbeats_received = link.heartbeats_received;
  counters.ignored = link.ignored;
  counters.dropped = link.dropped_invalid + parser.bad_crc + parser.bad_length +
                     parser.unknown_messages + parser.mavlink1_frames;
  counters.bytes_skipped = parser.bytes_skipped;
  counters.send_errors = link.send_errors;
  return counters;
}
std::vector<int> PhysicsServer::TakeSilentRobots() {
  std::vector<int> silent;
  silent.swap(impl_->silent_robots);
  return silent;
}
int PhysicsServer::wait_fd() const { return impl_->epoll_fd; }
World& PhysicsServer::world() { return impl_->world; }
const World& PhysicsServer::world() const { return impl_->world; }
const RobotCounters& PhysicsServer::counters(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->endpoints.size()));
  return impl_->endpoints[robot].counters;
}

TimeNs RunRealtime(PhysicsServer* server, double realtime_factor, TimeNs duration_ns,
                   const std::atomic<bool>& stop) {
  const TimeNs step_ns = server->world().step_ns();
  clock::Timebase timebase(realtime_factor);
  timebase.Begin(MonotonicNowNs());
  TimeNs max_lag_ns = 0;
  for (int64_t steps = 0; !stop.load() && (duration_ns <= 0 || steps * step_ns < duration_ns);) {
    const TimeNs due_ns = timebase.WallOf((steps + 1) * step_ns);
    const TimeNs now_ns = MonotonicNowNs();
    if (now_ns < due_ns) {
      // Sleep until the step is due, waking early for packets (handled at once, so a command
      // takes effect at the next step).
      pollfd fd{server->wait_fd(), POLLIN, 0};
      const TimeNs wait_ns = due_ns - now_ns;
      const timespec timeout{static_cast<time_t>(wait_ns / kNsPerS),
                             static_cast<long>(wait_ns % kNsPerS)};
      if (ppoll(&fd, 1, &timeout, nullptr) > 0) server->Poll();
      continue;
    }
    max_lag_ns = std::max(max_lag_ns, timebase.LagNs((steps + 1) * step_ns, now_ns));
    server->Advance(1);
    ++steps;
  }
  return max_lag_ns;
}

}  // namespace sitlnet::physics

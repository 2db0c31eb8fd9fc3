// PhysicsServer: the World plus every robot's links (robot_link.h), stepped in one clock, with
// the pacing that waits for autopilots (docs/protocols.md).
#include <poll.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "clock/clock.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/robot_link.h"

namespace sitlnet::physics {

struct PhysicsServer::Impl {
  World world;
  // Per scenario robot (global index): what its links share (unused for robots the world does
  // not simulate); then every link, robot by robot, in protocol order.
  std::vector<RobotLinkContext> robots;
  std::vector<std::unique_ptr<RobotLink>> links;
  std::vector<size_t> link_begin;  // Robot r's links: [link_begin[r], link_begin[r + 1]).
  int epoll_fd = -1;
  bool use_epoll_pwait2 = true;  // Until the kernel or a seccomp profile refuses it.
  const TimeNs frame_gate_timeout_ns;         // 0: the clock never waits for autopilots
  const clock::Timebase* realtime = nullptr;  // Set: autopilots are served on the wall clock.
  bool has_autopilots = false;  // Some link is paced (ArduPilot, PX4): the frame gate applies.
  std::vector<std::pair<int, SilentAutopilot>> silent;  // (link kind, autopilot), as reported
  struct WatchedFd {
    RobotLink* link = nullptr;
    int fd = -1;
  };
  // What each epoll event points to (std::map: its nodes do not move).
  std::map<std::pair<RobotLink*, int>, WatchedFd> watched_fds;
  static constexpr int kEventBatch = 64;
  epoll_event events[kEventBatch];  // epoll's answers, reused (Poll and WaitAndPoll).
  // AdvanceRobotByRobot's buffers, reused: the robots to step now and their places in
  // world.robots(), and since when each robot may have been held.
  std::vector<RobotSteps> ready;
  std::vector<size_t> ready_slots;
  std::vector<TimeNs> held_since_ns;

  Impl(const Scenario& s, const ServerOptions& options)
      : world(s, options.world),
        robots(s.robots.size()),
        frame_gate_timeout_ns(std::max<TimeNs>(0, options.frame_gate_timeout_ns)) {}
  ~Impl() {
    if (epoll_fd >= 0) close(epoll_fd);
  }

  void Watch(RobotLink* link, int fd) {
    // The epoll event names the link and the fd (a PX4 link watches its listener and its
    // connection): one entry per pair, kept for the server's life (a reconnection adds one).
    WatchedFd& watched = watched_fds[{link, fd}];
    watched = {link, fd};
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.ptr = &watched;
    if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event) != 0) {
      throw Error(SystemErrorMessage("physics server: epoll_ctl", errno));
    }
  }

  // Polls until no link satisfies `waiting_for` (true) or the wall clock reaches `deadline_ns`
  // (false).
  template <typename Predicate>
  bool AwaitAnswers(TimeNs deadline_ns, Predicate waiting_for) {
    for (;;) {
      if (std::none_of(links.begin(), links.end(), waiting_for)) return true;
      const TimeNs left_ns = deadline_ns - MonotonicNowNs();
      if (left_ns <= 0) return false;
      WaitAndPoll(left_ns);
    }
  }

  // Sleeps until some watched fd is readable or `timeout_ns` passed, and handles what is
  // readable: one system call per wake-up (epoll_pwait2), not a poll and then a read of the set.
  void WaitAndPoll(TimeNs timeout_ns) {
    const timespec wait{static_cast<time_t>(timeout_ns / kNsPerS),
                        static_cast<long>(timeout_ns % kNsPerS)};
    int n = -1;
    if (use_epoll_pwait2) {
      n = epoll_pwait2(epoll_fd, events, kEventBatch, &wait, nullptr);
      // ENOSYS before Linux 5.11; EPERM (or another errno) where a container's seccomp profile
      // does not know the call: from then on epoll_wait, which every profile allows.
      if (n < 0 && errno != EINTR) use_epoll_pwait2 = false;
    }
    if (!use_epoll_pwait2) {
      // Milliseconds, rounded up (the deadline is looked at again after).
      n = epoll_wait(epoll_fd, events, kEventBatch,
                     static_cast<int>(std::min<TimeNs>((timeout_ns + kNsPerMs - 1) / kNsPerMs,
                                                       INT32_MAX)));
    }
    if (n <= 0) return;
    Dispatch(n);
    if (n == kEventBatch) Poll();  // More may be ready.
  }

  void Dispatch(int n) {
    for (int i = 0; i < n; ++i) {
      const WatchedFd& watched = *static_cast<const WatchedFd*>(events[i].data.ptr);
      watched.link->PollReadable(watched.fd);
    }
  }

  // The frame gate's silent-autopilot policy: an autopilot whose answer has not come within
  // frame_gate_timeout_ns of wall time is recorded for the caller's policy and not waited for
  // again until it answers (RobotLink::Mute).
  void MuteSilent(int robot) {
    for (size_t i = link_begin[robot]; i < link_begin[robot + 1]; ++i) {
      RobotLink& link = *links[i];
      if (!link.Awaited()) continue;  // Answered, or reported silent before.
      link.Mute();
      const UnansweredMessage words = link.unanswered();
      silent.push_back({link.kind, {link.robot, words.unanswered, words.expected}});
    }
  }

  // The frame gate holds the robot: one of its autopilots owes an answer (RobotLink::Awaited).
  bool Held(int robot) const {
    for (size_t i = link_begin[robot]; i < link_begin[robot + 1]; ++i) {
      if (links[i]->Awaited()) return true;
    }
    return false;
  }

  // Lockstep with autopilots (the frame gate): each robot steps as soon as its own autopilots
  // have answered, to the next step one of its links is due (or the iteration's end), and is
  // served there; no robot waits for another's autopilot (docs/physics.md, "Stepping an
  // iteration"). A robot's flight and messages depend only on its own links: the same bytes
  // as a barrier at every step would give. Robots ready together are stepped together, over
  // the step pool. The iteration ends when every robot has reached `steps`; what a paced link
  // is due there leaves at the next Advance's start.
  void AdvanceRobotByRobot(int steps) {
    const std::vector<int>& robots = world.robots();
    if (robots.empty()) return;
    const int64_t end = world.steps(robots.front()) + steps;
    // Per robot (in world order): since when the frame gate may have held it (its last serve or
    // step); an autopilot still silent frame_gate_timeout_ns later is muted and reported.
    held_since_ns.assign(robots.size(), MonotonicNowNs());
    for (;;) {
      ready.clear();
      TimeNs first_timeout_ns = std::numeric_limits<TimeNs>::max();
      bool stepping = false;
      for (size_t k = 0; k < robots.size(); ++k) {
        const int robot = robots[k];
        const int64_t left = end - world.steps(robot);
        if (left == 0) continue;
        stepping = true;
        if (Held(robot)) {
          first_timeout_ns = std::min(first_timeout_ns, held_since_ns[k] + frame_gate_timeout_ns);
          continue;
        }
        int chunk = static_cast<int>(left);
        for (size_t i = link_begin[robot]; i < link_begin[robot + 1]; ++i) {
          chunk = std::min(chunk, links[i]->StepsUntilDue());
        }
        ready.push_back({robot, chunk});
        ready_slots.push_back(k);
      }
      if (!stepping) break;
      if (!ready.empty()) {
        world.Advance(ready);
        const TimeNs now_ns = MonotonicNowNs();
        for (size_t j = 0; j < ready.size(); ++j) {
          const int robot = ready[j].robot;
          const bool at_end = world.steps(robot) == end;
          for (size_t i = link_begin[robot]; i < link_begin[robot + 1]; ++i) {
            if (!at_end || !links[i]->paced()) links[i]->Serve();
          }
          held_since_ns[ready_slots[j]] = now_ns;
        }
        ready_slots.clear();
        continue;
      }
      // Every robot still stepping waits for an answer.
      const TimeNs left_ns = first_timeout_ns - MonotonicNowNs();
      if (left_ns > 0) {
        WaitAndPoll(left_ns);
        continue;
      }
      // An answer that arrived while this thread waited for a CPU (a busy host) is in its
      // socket, unread: the clock was read before. Taken before anyone is named.
      Poll();
      const TimeNs now_ns = MonotonicNowNs();
      for (size_t k = 0; k < robots.size(); ++k) {
        if (world.steps(robots[k]) != end && held_since_ns[k] + frame_gate_timeout_ns <= now_ns) {
          MuteSilent(robots[k]);
        }
      }
    }
  }

  // Realtime hold: the world does not run ahead of the wall clock while an autopilot's answer is
  // awaited; it waits for the answer up to the wall instant of its next step. False if some
  // answer has not come by then.
  bool AwaitAnswersOnWallClock() {
    return AwaitAnswers(
        realtime->WallOf(world.now_ns() + world.step_ns()),
        [](const std::unique_ptr<RobotLink>& link) { return link->AnswerOutstanding(); });
  }

  void Poll() {
    // Enough rounds to see every socket once (epoll rotates its ready list; two sockets a
    // robot), no more: a sustained flood cannot keep Poll from returning.
    const size_t rounds = 1 + 2 * static_cast<size_t>(world.robot_count()) / kEventBatch;
    for (size_t round = 0; round < rounds; ++round) {
      const int n = epoll_wait(epoll_fd, events, kEventBatch, 0);
      if (n <= 0) return;
      Dispatch(n);
      if (n < kEventBatch) return;
    }
  }

  std::vector<int> CollectCommands(TimeNs timeout_ns) {
    const TimeNs deadline_ns = MonotonicNowNs() + timeout_ns;
    std::vector<int> missing;
    Poll();
    for (;;) {
      missing.clear();
      for (const std::unique_ptr<RobotLink>& link : links) {
        if (link->LockstepCommandMissing()) missing.push_back(link->robot);
      }
      const TimeNs left_ns = deadline_ns - MonotonicNowNs();
      if (missing.empty() || left_ns <= 0) return missing;
      WaitAndPoll(left_ns);
    }
  }

  // Realtime pacing: what autopilots are due now leaves at the wall instant of the world's
  // virtual time, not earlier (the physics computes an iteration ahead of the wall clock).
  void HoldForWallClock() {
    if (realtime == nullptr || world.robot_count() == 0) return;
    if (std::none_of(links.begin(), links.end(), [](const std::unique_ptr<RobotLink>& link) {
          return link->paced() && link->DueNow();
        })) {
      return;
    }
    // The coordinator's timebase is on CLOCK_MONOTONIC (clock::SystemWallClock), as here.
    const TimeNs wall_ns = realtime->WallOf(world.now_ns());
    if (wall_ns > MonotonicNowNs()) clock::SystemWallClock().SleepUntilNs(wall_ns);
  }

  void Advance(int steps) {
    Poll();
    // With the frame gate (lockstep), a reply due at the end of the previous Advance leaves now,
    // at the start of this one: what the autopilot does in answer (its next frame, its radio
    // traffic) then falls in this iteration, whose network part drains its TAP after physics,
    // instead of racing the previous iteration's.
    HoldForWallClock();
    for (const std::unique_ptr<RobotLink>& link : links) {
      if (link->paced()) link->Serve();
    }
    if (frame_gate_timeout_ns > 0 && has_autopilots) {
      AdvanceRobotByRobot(steps);
      return;
    }
    // One clock for every robot: chunks end where some link is due (realtime, no frame gate,
    // or no autopilot).
    for (int remaining = steps; remaining > 0;) {
      int chunk = remaining;
      if (realtime != nullptr && world.robot_count() > 0 && !AwaitAnswersOnWallClock()) {
        chunk = 1;  // Not answered yet: the world follows the wall clock a step at a time.
      }
      for (const std::unique_ptr<RobotLink>& link : links) {
        chunk = std::min(chunk, link->StepsUntilDue());
      }
      world.Advance(chunk);
      remaining -= chunk;
      HoldForWallClock();
      for (const std::unique_ptr<RobotLink>& link : links) link->Serve();
    }
  }
};

PhysicsServer::PhysicsServer(const Scenario& scenario, const ServerOptions& options)
    : impl_(std::make_unique<Impl>(scenario, options)) {
  SITLNET_DEMAND(options.frame_gate_timeout_ns == 0 || options.autopilot_wall_clock == nullptr);
  impl_->epoll_fd = epoll_create1(EPOLL_CLOEXEC);
  if (impl_->epoll_fd < 0) throw Error(SystemErrorMessage("physics server: epoll_create1", errno));
  const auto make_sockets = [&] {
    for (const RobotPlan& plan : scenario.robots) {
      impl_->link_begin.push_back(impl_->links.size());
      if (!impl_->world.simulates(plan.index)) continue;  // Another host's robot: no links.
      RobotLinkContext& robot = impl_->robots[plan.index];
      robot.world = &impl_->world;
      robot.robot = plan.index;
      RobotLinkSetup setup;
      setup.scenario = &scenario;
      setup.plan = &plan;
      setup.robot = &robot;
      setup.who = scenario.source_path + ": robot \"" + plan.name + "\"";
      setup.periodic_states = options.periodic_states;
      setup.watch = [impl = impl_.get()](RobotLink* link, int fd) { impl->Watch(link, fd); };
      for (std::unique_ptr<RobotLink>& link : MakeRobotLinks(setup)) {
        impl_->has_autopilots |= link->paced();
        impl_->links.push_back(std::move(link));
      }
    }
    impl_->link_begin.push_back(impl_->links.size());
  };
  if (options.make_sockets) {
    options.make_sockets(make_sockets);
  } else {
    make_sockets();
  }
  if (impl_->has_autopilots) impl_->realtime = options.autopilot_wall_clock;
}

PhysicsServer::~PhysicsServer() = default;

void PhysicsServer::Poll() { impl_->Poll(); }
void PhysicsServer::DropFromLockstep(int robot) {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  RobotLinkContext& context = impl_->robots[robot];
  if (context.dropped) return;
  context.dropped = true;
  context.motors_cut = true;
  for (size_t i = impl_->link_begin[robot]; i < impl_->link_begin[robot + 1]; ++i) {
    impl_->links[i]->OnDropped();
  }
  impl_->world.SetRotorTarget(robot, RotorSpeeds{});  // as an ESC failsafe: spin down
  ++context.counters.failsafe_cuts;
}
void PhysicsServer::SendStates() {
  for (const std::unique_ptr<RobotLink>& link : impl_->links) link->SendLockstepState();
}
std::vector<int> PhysicsServer::CollectCommands(TimeNs timeout_ns) {
  return impl_->CollectCommands(timeout_ns);
}
void PhysicsServer::Advance(int steps) { impl_->Advance(steps); }
bool PhysicsServer::has_frame_gated_robots() const { return impl_->has_autopilots; }
bool PhysicsServer::spoke(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  for (size_t i = impl_->link_begin[robot]; i < impl_->link_begin[robot + 1]; ++i) {
    if (impl_->links[i]->spoke()) return true;
  }
  return false;
}
std::optional<Px4Counters> PhysicsServer::px4_counters(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  std::optional<Px4Counters> counters;
  for (size_t i = impl_->link_begin[robot]; i < impl_->link_begin[robot + 1]; ++i) {
    impl_->links[i]->ReportPx4(&counters);
  }
  return counters;
}
std::vector<SilentAutopilot> PhysicsServer::TakeSilentAutopilots() {
  // Grouped by protocol (the caller names the robots of one protocol in one message), robots
  // in order (each robot's timeout runs on its own: several may fall silent in one call).
  std::stable_sort(impl_->silent.begin(), impl_->silent.end(), [](const auto& a, const auto& b) {
    return std::pair(a.first, a.second.robot) < std::pair(b.first, b.second.robot);
  });
  std::vector<SilentAutopilot> silent;
  for (auto& [kind, autopilot] : impl_->silent) silent.push_back(std::move(autopilot));
  impl_->silent.clear();
  return silent;
}
AutopilotRate PhysicsServer::autopilot_rate(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  return impl_->robots[robot].answers.Read();
}
int PhysicsServer::wait_fd() const { return impl_->epoll_fd; }
World& PhysicsServer::world() { return impl_->world; }
const World& PhysicsServer::world() const { return impl_->world; }
const RobotCounters& PhysicsServer::counters(int robot) const {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  return impl_->robots[robot].counters;
}

TimeNs RunRealtime(PhysicsServer* server, double realtime_factor, TimeNs duration_ns,
                   int stop_fd) {
  const TimeNs step_ns = server->world().step_ns();
  clock::Timebase timebase(realtime_factor);
  timebase.Begin(MonotonicNowNs());
  TimeNs max_lag_ns = 0;
  // The server's socket and the stop: a negative fd is ignored by ppoll.
  pollfd fds[2] = {{server->wait_fd(), POLLIN, 0}, {stop_fd, POLLIN, 0}};
  // Behind the wall clock no step sleeps: the stop is then looked at every kStopCheckSteps.
  constexpr int64_t kStopCheckSteps = 64;
  for (int64_t steps = 0; duration_ns <= 0 || steps * step_ns < duration_ns;) {
    const TimeNs due_ns = timebase.WallOf((steps + 1) * step_ns);
    const TimeNs now_ns = MonotonicNowNs();
    if (now_ns < due_ns) {
      // Sleep until the step is due, waking early for packets (handled at once, so a command
      // takes effect at the next step) or the stop.
      const TimeNs wait_ns = due_ns - now_ns;
      const timespec timeout{static_cast<time_t>(wait_ns / kNsPerS),
                             static_cast<long>(wait_ns % kNsPerS)};
      if (ppoll(fds, 2, &timeout, nullptr) > 0) {
        if (fds[1].revents & POLLIN) break;
        if (fds[0].revents) server->Poll();
      }
      continue;
    }
    if (stop_fd >= 0 && steps % kStopCheckSteps == 0) {
      pollfd stop{stop_fd, POLLIN, 0};
      if (poll(&stop, 1, 0) == 1) break;
    }
    max_lag_ns = std::max(max_lag_ns, timebase.LagNs((steps + 1) * step_ns, now_ns));
    server->Advance(1);
    ++steps;
  }
  return max_lag_ns;
}

}  // namespace sitlnet::physics

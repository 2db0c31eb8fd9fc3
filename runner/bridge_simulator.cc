#include "runner/bridge_simulator.h"

#include <sys/epoll.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace sitlnet::runner {

BridgeSimulator::BridgeSimulator(const Scenario& scenario, tapbridge::BridgeCore* bridge,
                                 coordinator::Pacing pacing, double realtime_factor)
    : bridge_(*bridge),
      pacing_(pacing),
      realtime_factor_(realtime_factor),
      network_step_ns_(scenario.network_step_ns) {}

BridgeSimulator::~BridgeSimulator() {
  if (end_timer_fd_ >= 0) {
    loop_.Remove(end_timer_fd_);
    close(end_timer_fd_);
  }
}

void BridgeSimulator::MoveStations(const proto::coord::Poses& poses) {
  const int robots = std::min(bridge_.robot_count(), poses.position_m_size() / 3);
  for (int i = 0; i < robots; ++i) {
    bridge_.SetPosition(i, poses.position_m(3 * i), poses.position_m(3 * i + 1),
                        poses.position_m(3 * i + 2));
  }
}

void BridgeSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End*,
                                   coordinator::IterationContext&) {
  MoveStations(start.poses());
  if (pacing_ == coordinator::Pacing::kLockstep) {
    for (TimeNs until = start.start_ns() + network_step_ns_; until <= start.end_ns();
         until += network_step_ns_) {
      bridge_.StepLockstep(until);
    }
    return;
  }
  const auto wall_of = [&](TimeNs virtual_ns) {
    return wall_origin_ns_ + static_cast<TimeNs>(virtual_ns / realtime_factor_);
  };
  if (!started_) {
    // Virtual start_ns is now: the coordinator just began this iteration.
    wall_origin_ns_ = MonotonicNowNs() - static_cast<TimeNs>(start.start_ns() / realtime_factor_);
    bridge_.StartRealtime(&loop_, wall_origin_ns_);
    end_timer_fd_ = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    if (end_timer_fd_ < 0) throw Error(SystemErrorMessage("runner: timerfd_create", errno));
    loop_.Add(end_timer_fd_, EPOLLIN, [this](uint32_t) {
      uint64_t expirations = 0;
      if (read(end_timer_fd_, &expirations, sizeof expirations) > 0) end_reached_ = true;
    });
    started_ = true;
  }
  const TimeNs wall_end = wall_of(start.end_ns());
  // CLOCK_MONOTONIC, as MonotonicNowNs; an instant already past fires at once.
  itimerspec at{};
  at.it_value.tv_sec = wall_end / kNsPerS;
  at.it_value.tv_nsec = wall_end % kNsPerS;
  uint64_t stale = 0;  // An expiry of the last iteration not yet read must not end this one.
  if (read(end_timer_fd_, &stale, sizeof stale) < 0 && errno != EAGAIN) {
    throw Error(SystemErrorMessage("runner: read end timer", errno));
  }
  timerfd_settime(end_timer_fd_, TFD_TIMER_ABSTIME, &at, nullptr);
  end_reached_ = false;
  // At least one non-blocking turn: when the coordinator runs behind real
  // time, wall_end is already past, and without it the TAPs were never read
  // (64 robots in realtime pacing moved 0 frames in 30 s).
  loop_.RunOnce(0);
  for (TimeNs now = MonotonicNowNs(); !end_reached_ && now < wall_end; now = MonotonicNowNs()) {
    // The end timer wakes the loop on time; the millisecond timeout (rounded
    // up) is only a backstop. The bridge's own timerfd writes deliveries at
    // their exact instants meanwhile.
    loop_.RunOnce(static_cast<int>((wall_end - now + kNsPerMs - 1) / kNsPerMs));
  }
}

}  // namespace sitlnet::runner

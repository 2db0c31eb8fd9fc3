#include <algorithm>

#include "network_side/network_side.h"

namespace sitlnet::network_side {

BridgeSimulator::BridgeSimulator(const Scenario& scenario, tapbridge::BridgeCore* bridge,
                                 coordinator::Pacing pacing, double realtime_factor)
    : bridge_(*bridge),
      pacing_(pacing),
      timebase_(realtime_factor),
      network_step_ns_(scenario.network_step_ns) {}

void BridgeSimulator::MoveStations(const proto::coord::Poses& poses) {
  const int robots = std::min(bridge_.robot_count(), poses.position_m_size() / 3);
  for (int i = 0; i < robots; ++i) {
    bridge_.SetPosition(i, poses.position_m(3 * i), poses.position_m(3 * i + 1),
                        poses.position_m(3 * i + 2));
  }
}

void BridgeSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End*,
                                   IterationContext&) {
  MoveStations(start.poses());
  if (pacing_ == coordinator::Pacing::kLockstep) {
    for (TimeNs until = start.start_ns() + network_step_ns_; until <= start.end_ns();
         until += network_step_ns_) {
      bridge_.StepLockstep(until);
    }
    return;
  }
  if (!started_) {
    // Virtual start_ns is now: the coordinator just began this iteration.
    timebase_.BeginAt(start.start_ns(), MonotonicNowNs());
    bridge_.StartRealtime(&loop_, timebase_);
    started_ = true;
  }
  const TimeNs wall_end = timebase_.WallOf(start.end_ns());
  // At least one non-blocking turn: when the coordinator runs behind real
  // time, wall_end is already past, and without it the TAPs were never read
  // (64 robots in realtime pacing moved 0 frames in 30 s).
  loop_.RunOnce(0);
  for (TimeNs now = MonotonicNowNs(); now < wall_end; now = MonotonicNowNs()) {
    // epoll's millisecond timeout, rounded up; the bridge's own timerfd
    // writes deliveries at their exact instants meanwhile.
    loop_.RunOnce(static_cast<int>((wall_end - now + kNsPerMs - 1) / kNsPerMs));
  }
}

}  // namespace sitlnet::network_side

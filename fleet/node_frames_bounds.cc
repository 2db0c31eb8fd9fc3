#include "fleet/node_frames_bounds.h"

#include <algorithm>
#include <vector>

namespace sitlnet::fleet {
namespace {

// Linux errnos end at 133 (EHWPOISON); 4095 is the kernel's MAX_ERRNO, the most a syscall returns.
constexpr int kMaxErrno = 4095;

}  // namespace

std::optional<std::string> FindBrokenBound(const proto::node::NodeFrames& frames,
                                           const NodeSlice& node,
                                           std::span<const std::string> robot_names,
                                           bool realtime) {
  const int robot_count = static_cast<int>(robot_names.size());
  std::vector<bool> seen(robot_names.size(), false);
  for (const proto::node::FrameBatch& batch : frames.batches()) {
    const int robot = batch.robot();
    if (robot < 0 || robot >= robot_count) {
      return "sent frames for robot " + std::to_string(robot) + ", which is not in the scenario (" +
             std::to_string(robot_count) + " robots)";
    }
    // Built only for a refusal: an accepted batch costs no string.
    const auto name = [&] { return "robot '" + robot_names[robot] + "'"; };
    if (!std::binary_search(node.robots.begin(), node.robots.end(), robot)) {
      return "sent frames for " + name() + ", which is not one of its robots";
    }
    // A second batch would double the robot's turn: the bridge reads one turn per step.
    if (seen[robot]) return "sent two batches for " + name() + " in one turn";
    seen[robot] = true;
    if (batch.frames_size() > static_cast<int>(tapbridge::kMaxFramesPerRobotPerTurn)) {
      return "sent " + std::to_string(batch.frames_size()) + " frames for " + name() +
             " in one turn, more than the bridge reads (" +
             std::to_string(tapbridge::kMaxFramesPerRobotPerTurn) + ")";
    }
    for (const std::string& frame : batch.frames()) {
      // An empty frame would read as "none waits" (tapbridge::Port::Read returns 0).
      if (frame.empty()) return "sent an empty frame for " + name() + " (a TAP read gives a byte)";
      if (frame.size() > kMaxNodeFrameBytes) {
        return "sent a frame of " + std::to_string(frame.size()) + " bytes for " + name() +
               ", longer than " + std::to_string(kMaxNodeFrameBytes) +
               " (a node cuts longer frames to that)";
      }
    }
    // Realtime: one read instant per frame, or a frame would be timed by another's; lockstep: none.
    if (batch.read_ns_size() != (realtime ? batch.frames_size() : 0)) {
      return "sent " + std::to_string(batch.read_ns_size()) + " read instants for " +
             std::to_string(batch.frames_size()) + " frames of " + name();
    }
    if (batch.read_errno() < 0 || batch.read_errno() > kMaxErrno) {
      return "sent read_errno " + std::to_string(batch.read_errno()) + " for " + name() +
             ", which is no errno (1 to " + std::to_string(kMaxErrno) + ")";
    }
  }
  return std::nullopt;
}

std::optional<std::string> FindBrokenWriteLateness(const proto::node::NodeFrames& frames,
                                                   int writes_sent) {
  if (frames.write_late_ns_size() <= writes_sent) return std::nullopt;
  return "reports " + std::to_string(frames.write_late_ns_size()) +
         " writes, but its Start carried " + std::to_string(writes_sent);
}

}  // namespace sitlnet::fleet

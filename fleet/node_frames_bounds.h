// The bounds of node_link.proto on what a node sends up (NodeFrames), checked before any of it
// reaches the bridge.
#ifndef SITLNET_FLEET_NODE_FRAMES_BOUNDS_H_
#define SITLNET_FLEET_NODE_FRAMES_BOUNDS_H_

#include <optional>
#include <span>
#include <string>

#include "fleet/fleet.h"

namespace sitlnet::fleet {

// Largest frame a node may send: a longer one is cut to this length by the node, so that the
// bridge still drops it as oversize (tapbridge.h, EnterFrame) and no message carries more.
inline constexpr size_t kMaxNodeFrameBytes = tapbridge::kMax80211EthernetFrameBytes + 1;

// The first bound `frames` breaks, as the end of a sentence naming the robot ("sent 257 frames
// for robot 'c' in one turn, more than the bridge reads (256)"); nullopt when it keeps them all.
// `node`: the sender's robots; `robot_names`: the scenario's, by index. `realtime`: the run's
// pacing, which wants one read instant (FrameBatch.read_ns) per frame; lockstep wants none.
std::optional<std::string> FindBrokenBound(const proto::node::NodeFrames& frames,
                                           const NodeSlice& node,
                                           std::span<const std::string> robot_names, bool realtime);

// Realtime: what is wrong with the writes' lateness `frames` reports in the End that answers a
// Start of `writes_sent` writes ("reports 3 writes, but its Start carried 2"): one lateness per
// write, so at most that many; nullopt when it keeps that bound.
std::optional<std::string> FindBrokenWriteLateness(const proto::node::NodeFrames& frames,
                                                   int writes_sent);

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_FRAMES_BOUNDS_H_

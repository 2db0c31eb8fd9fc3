// The central host's end of the node links (issue 35): accepting the scenario's node hosts, and
// driving them as the run's physics, one lockstep iteration at a time. Messages:
// docs/protocols.md, "Central host <-> node host".
#ifndef SITLNET_FLEET_NODE_LINK_H_
#define SITLNET_FLEET_NODE_LINK_H_

#include <memory>
#include <string>
#include <vector>

#include "coordinator/connector.h"
#include "coordinator/pacer.h"
#include "coordinator/remote_connector.h"
#include "fleet/fleet.h"

namespace sitlnet::fleet {

// One joined node host: its authenticated channel (behind a RemoteConnector of role node), its
// robots and how error lines name it.
class NodeLink {
 public:
  // `peer`: accepted with role node and robots equal to `slice.robots`.
  NodeLink(const Scenario& scenario, NodeSlice slice, coordinator::AcceptedPeer peer);

  const NodeSlice& slice() const { return slice_; }
  // "node 'n1' (robots c, d)".
  const std::string& Describe() const { return description_; }
  // Where it connected from: "10.88.0.5:40312", or "a unix socket".
  const std::string& address() const { return address_; }
  // Start, CommandsCollected, End and Stop over the channel; its errors name the node.
  coordinator::RemoteConnector& connector() { return connector_; }

 private:
  NodeSlice slice_;
  std::string description_;
  std::string address_;
  coordinator::RemoteConnector connector_;
};

// Accepts the node hosts of `nodes` (slices of `scenario`'s robots) on `listener`, with
// expect.role set to node. A node whose name is not in `nodes`, or whose Hello claims other
// robots than its slice, or sends initial poses of another count, is refused before Welcome:
// Error naming it. A second node of one name: Error "two nodes claim robot 'c': node 'n1' from
// A and node 'n1' from B". At limits.deadline_ns: Error "node 'n2' (robots e, f) did not connect
// to <endpoint> within <timeout> ms". On any error the nodes that joined are sent Stop with it.
// Returns the links in the order of `nodes`; empty if limits.interrupt_fd fired.
std::vector<std::unique_ptr<NodeLink>> AcceptNodes(coordinator::Listener& listener,
                                                   const Scenario& scenario,
                                                   const std::vector<NodeSlice>& nodes,
                                                   coordinator::HandshakeExpectation expect,
                                                   const coordinator::WaitLimits& limits);

// The run's physics when the robots live on node hosts: every iteration is one round trip per
// node. Begin sends each node Start with a NodeStart of what the bridge wrote to its robots;
// AwaitCommandsCollected waits for every node's CommandsCollected and hands its NodeFrames to
// `ports`; Finish waits for every End and merges the poses in scenario order (busy_ns: the
// largest). Stop stops every node. A node that fails, closes or stays silent throws one line
// naming it, its robots and the iteration. Lockstep pacing needs one network step per
// iteration, for now: the constructor refuses others in one line.
// Realtime pacing (docs/scale-out.md, "Realtime pacing"): no CommandsCollected; each node's End
// carries the frames it read during the iteration (a NodeFrames in End.payload), handed to
// `ports` when it arrives, and how late it wrote the deliveries its Start carried.
class FleetPhysicsConnector final : public coordinator::Connector {
 public:
  // `nodes[i]` feeds node i of `ports` (built from the same slices, in the same order).
  FleetPhysicsConnector(const Scenario& scenario, coordinator::Pacing pacing,
                        std::vector<std::unique_ptr<NodeLink>> nodes, RemotePorts* ports);

  const proto::coord::Poses& initial_poses() const override { return initial_poses_; }
  void Begin(const proto::coord::Start& start, const coordinator::WaitLimits& limits) override;
  bool AwaitCommandsCollected(uint64_t iteration, const coordinator::WaitLimits& limits) override;
  bool Finish(uint64_t iteration, proto::coord::End* end,
              const coordinator::WaitLimits& limits) override;
  void Stop(const std::string& reason) override;

  // Each node's link so far, in the order of `nodes`.
  std::vector<FleetLinkStats> link_stats() const;

 private:
  // Realtime: hands the NodeFrames of node_end_ (node `node`'s End) to ports_; throws Error
  // naming the node if it does not parse or reports more writes than its Start carried.
  void ReceiveRealtimeFrames(int node, uint64_t iteration);

  size_t robot_count_;
  bool realtime_;
  std::vector<std::unique_ptr<NodeLink>> nodes_;
  RemotePorts& ports_;
  std::vector<int> writes_sent_;  // By node: the writes of its last Start.
  proto::coord::Poses initial_poses_;
  proto::coord::Start start_;  // Reused: one per node per iteration.
  proto::coord::End node_end_;
};

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_LINK_H_

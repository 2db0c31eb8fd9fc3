// sitlnet fleet: one scenario's robots spread over several node hosts (issue 35). A node host
// keeps its robots' namespaces and wlan0 TAPs. The central host keeps the one medium and its
// bridge (tapbridge::BridgeCore), which reaches those robots through the ports here. The
// messages between them: proto/sitlnet/node_link.proto, docs/protocols.md.
#ifndef SITLNET_FLEET_FLEET_H_
#define SITLNET_FLEET_FLEET_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "coordinator/link_meter.h"
#include "scenario/scenario.h"
#include "sitlnet/node_link.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::fleet {

//------------------------------------ Nodes ----------------------------------

// The robots one node host runs: the node's name and their indices in the scenario, ascending.
// The scenario's own plan of a node (Scenario::nodes), so a run passes scenario.nodes as is.
using NodeSlice = NodePlan;

// "node 'n1' (robots c, d)": how every message names a node.
std::string DescribeNode(const Scenario& scenario, const NodeSlice& node);

// What a node's link cost over a run, measured by the central (summary.json "fleet_links"):
// one round trip per iteration, from sending its Start to reading its End.
struct FleetLinkStats {
  std::string node;         // Its name.
  std::string description;  // DescribeNode.
  coordinator::LinkStats link;
};

// The scenario hash a node host and its central prove to each other: coordinator::ScenarioHash
// without timing.duration_ms, so that the central's --duration alone sets how long the run goes.
uint64_t NodeScenarioHash(const Scenario& scenario);

//--------------------------- Central host: remote ports ----------------------

// The central host's ports of the robots on node hosts. A node's NodeFrames are queued per
// robot, and the bridge reads them through the robots' ports as it would read their TAPs; what
// the bridge writes to them is collected per node as NodeWrites. Use from the bridge's thread.
//
// Receive throws on a NodeFrames that breaks a bound of node_link.proto, and the link is to end
// there: an honest node never sends one, so its sender is broken or hostile (docs/security.md,
// finding 4). What robots send (runts, oversize, foreign source MACs) is theirs: the bridge
// counts it, as on one host.
//
// Realtime pacing (a `realtime` timebase: the run's, begun by the coordinator before iteration
// 0): each port has a descriptor that polls readable while frames wait, so the bridge's realtime
// driver reads them as it reads a TAP, at the instant they are here. The ports measure, per
// node and in wall time, how late each frame entered (its read here past the node's read_ns)
// and how late the node wrote what came down (NodeFrames.write_late_ns), and stamp each write
// with the virtual time it was written here (Write.due_ns).
class RemotePorts {
 public:
  // `nodes`: slices of `scenario`'s robots, no robot on two. `realtime`: null in lockstep; else
  // not owned, and it must outlive this.
  RemotePorts(const Scenario& scenario, std::vector<NodeSlice> nodes,
              const clock::Timebase* realtime = nullptr);
  ~RemotePorts();
  RemotePorts(const RemotePorts&) = delete;
  RemotePorts& operator=(const RemotePorts&) = delete;

  // Port of robot `robot` (on one of the nodes), for BridgeOptions::open_port. It has no
  // descriptor (fd() is -1), so only the lockstep driver reads it. It must not outlive this
  // object. Closing it drops the robot's queued frames, as closing a TAP does.
  std::unique_ptr<tapbridge::Port> Open(int robot);

  // Queues the frames node `node` drained, behind any the bridge has not read yet. If `frames`
  // breaks a bound, queues none of it and throws Error naming the node, the robot and the bound:
  // "node 'n1' (robots c, d): sent 257 frames for robot 'c' in one turn, more than ...".
  // Frames of a robot whose port is closed are dropped and counted (frames_dropped_closed).
  void Receive(int node, const proto::node::NodeFrames& frames);

  // What the bridge wrote to node `node`'s robots since the last call; empties its outbox.
  proto::node::NodeWrites TakeWrites(int node);

  // Frames that arrived for `robot` while its port was closed (not opened yet, or detached).
  uint64_t frames_dropped_closed(int robot) const;

  // Realtime: how late node `node`'s frames entered the medium (the wall time of their read here
  // past that of the node's read_ns, which includes the node clock's offset: one link delay), and
  // how late the node wrote the deliveries sent to it (its own measure, in wall time too). Empty
  // in lockstep.
  tapbridge::LatenessStats LateEntries(int node) const;
  tapbridge::LatenessStats LateWrites(int node) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_FLEET_H_

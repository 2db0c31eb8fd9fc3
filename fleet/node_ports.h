// The node host's end of the node link (issue 35): its robots' ports (their wlan0 TAPs), drained
// up and written from what comes down, around the physics of its robots.
#ifndef SITLNET_FLEET_NODE_PORTS_H_
#define SITLNET_FLEET_NODE_PORTS_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "clock/clock.h"
#include "coordinator/connector.h"
#include "fleet/fleet.h"

namespace sitlnet::fleet {

// The ports of one node's robots. Drain reads them as the central bridge reads local ports: per
// robot in scenario order, up to the bridge's turn (tapbridge::kMaxFramesPerRobotPerTurn), each
// frame cut to kMaxNodeFrameBytes. A robot whose read failed is read no more: the bridge detaches
// it when the error reaches it (FrameBatch.read_errno).
class NodePorts {
 public:
  using OpenPort = std::function<std::unique_ptr<tapbridge::Port>(int robot)>;
  // Opens the port of every robot of `slice` (for TAPs: tapbridge::TapPort).
  NodePorts(NodeSlice slice, const OpenPort& open);

  const NodeSlice& slice() const { return slice_; }
  // One turn of every robot into `frames` (cleared first); robots with nothing to say are left
  // out.
  void Drain(proto::node::NodeFrames* frames);
  // Realtime: reads the robots' ports as frames arrive, until wall instant `deadline_ns`
  // (CLOCK_MONOTONIC; at least one pass), into `frames`' batches (one per robot, kept across
  // calls until cleared). A robot's batch holds at most one bridge turn; the rest waits in its
  // TAP. Each frame's FrameBatch.read_ns is the earliest it can have been written: `timebase`'s
  // virtual time when its port was last seen empty (while polled, its arrival; after the physics
  // ran, the previous call's end), and not before 0.
  void ReadUntil(TimeNs deadline_ns, const clock::Timebase& timebase,
                 proto::node::NodeFrames* frames);
  // Writes `writes` to the robots' ports in order. Throws Error, writing none, if one names a
  // robot not of this node or a frame that is not there (the central is broken). With
  // `realtime`, appends to `late_ns` how late each was written: its wall instant past that of
  // its Write.due_ns on `realtime` (0 if not past).
  void Write(const proto::node::NodeWrites& writes, const clock::Timebase* realtime = nullptr,
             google::protobuf::RepeatedField<int64_t>* late_ns = nullptr);
  // Writes to `robot` that its port refused (tapbridge::Port::Write's -errno), so far.
  uint64_t write_errors(int robot) const;

 private:
  struct Robot {
    int index = 0;
    std::unique_ptr<tapbridge::Port> port;
    bool read_failed = false;
    TimeNs seen_empty_wall_ns = 0;  // When a poll or read last found its port empty.
    uint64_t write_errors = 0;
  };
  Robot* Find(int robot);

  NodeSlice slice_;
  std::vector<Robot> robots_;  // In slice order.
  std::vector<uint8_t> buffer_;
};

// A node host's Simulator for ServeIterations: around its robots' physics (`physics`, poses of
// its robots only, in slice order), it writes what each Start brings down (a NodeStart) to the
// robots' ports first, and drains them when the physics reports CommandsCollected, whose payload
// then carries the frames (a NodeFrames) up. The physics must report it at most once an
// iteration; if it does not, it is reported after the iteration, before End.
//
// Realtime pacing (a `realtime` timebase, shared with the physics' autopilot clock): the first
// Start begins it (its virtual start is now on this host's clock), and a Start that comes before
// its instant on it moves it earlier. The deliveries are written at
// once, then the physics runs, then the ports are read as frames arrive until the wall instant of
// the iteration's end, and End carries the frames and the writes' lateness (a NodeFrames in
// End.payload) and the physics' own wall time as busy_ns.
class NodeSimulator final : public coordinator::Simulator {
 public:
  NodeSimulator(coordinator::Simulator* physics, NodePorts* ports,
                clock::Timebase* realtime = nullptr)
      : physics_(*physics), ports_(*ports), realtime_(realtime) {}

  proto::coord::Poses InitialPoses() override { return physics_.InitialPoses(); }
  // Throws Error if the Start carries no NodeStart that parses, or NodePorts::Write refuses it.
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;

 private:
  void RunRealtimeIteration(const proto::coord::Start& start,
                            const proto::node::NodeStart& node_start, proto::coord::End* end,
                            coordinator::IterationContext& context);

  coordinator::Simulator& physics_;
  NodePorts& ports_;
  clock::Timebase* realtime_;
  bool realtime_begun_ = false;
  proto::node::NodeFrames frames_;  // Realtime: reused.
};

// The Hello of a node host: its robots and their initial poses, for HandshakeWithCoordinator.
proto::coord::Hello NodeHello(const NodeSlice& slice, coordinator::Simulator& node);

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_PORTS_H_

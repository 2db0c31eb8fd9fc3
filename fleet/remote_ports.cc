// The central host's ports of robots on node hosts: frames a node drained wait here until the
// bridge reads them, in the order the node read them; writes wait in the node's outbox.
#include <algorithm>
#include <cstring>
#include <deque>
#include <functional>

#include "fleet/fleet.h"
#include "fleet/node_frames_bounds.h"
#include "fleet/node_outbox.h"

namespace sitlnet::fleet {
namespace {

// One robot's frames between the node's drain and the bridge's read.
struct RobotQueue {
  int node = -1;                   // Index of its node; -1: on none.
  bool open = false;               // Its port exists.
  std::deque<std::string> frames;  // Oldest first.
  int read_errno = 0;              // The node's TAP read failed after `frames`.
  uint64_t dropped_closed = 0;
};

class RemotePort : public tapbridge::Port {
 public:
  RemotePort(int robot, RobotQueue* queue, NodeOutbox* outbox)
      : robot_(robot), queue_(queue), outbox_(outbox) {
    queue_->open = true;
  }
  // A closed TAP drops what it held; so does a closed remote port.
  ~RemotePort() override {
    queue_->open = false;
    queue_->frames.clear();
    queue_->read_errno = 0;
  }

  ssize_t Read(std::span<uint8_t> buffer) override {
    if (queue_->frames.empty()) return -queue_->read_errno;  // 0: none waits.
    const std::string& frame = queue_->frames.front();
    const size_t length = std::min(frame.size(), buffer.size());  // Cut, as a TAP read does.
    std::memcpy(buffer.data(), frame.data(), length);
    queue_->frames.pop_front();
    return static_cast<ssize_t>(length);
  }

  // Always written here: the frame reaches the TAP with the node's next NodeWrites.
  int Write(std::span<const uint8_t> frame) override {
    outbox_->Add(robot_, frame);
    return 0;
  }

  // The node's TAP counts its drops; they do not come up the link yet.
  std::optional<uint64_t> KernelTxDropped() override { return std::nullopt; }

 private:
  int robot_;
  RobotQueue* queue_;
  NodeOutbox* outbox_;
};

}  // namespace

struct RemotePorts::Impl {
  std::vector<NodeSlice> nodes;
  std::vector<std::string> node_descriptions;  // DescribeNode, for error lines.
  std::vector<std::string> robot_names;
  std::vector<RobotQueue> robots;
  std::vector<NodeOutbox> outboxes;  // By node.
};

RemotePorts::RemotePorts(const Scenario& scenario, std::vector<NodeSlice> nodes)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.robots.resize(scenario.robots.size());
  for (const RobotPlan& robot : scenario.robots) impl.robot_names.push_back(robot.name);
  for (size_t node = 0; node < nodes.size(); ++node) {
    const std::vector<int>& robots = nodes[node].robots;
    // Ascending: FindBrokenBound looks robots up by binary search.
    SITLNET_DEMAND(std::adjacent_find(robots.begin(), robots.end(), std::greater_equal<int>()) ==
                   robots.end());
    for (const int robot : robots) {
      SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl.robots.size()));
      SITLNET_DEMAND(impl.robots[robot].node == -1);  // On one node only.
      impl.robots[robot].node = static_cast<int>(node);
    }
    impl.node_descriptions.push_back(DescribeNode(scenario, nodes[node]));
  }
  impl.nodes = std::move(nodes);
  impl.outboxes.resize(impl.nodes.size());
}

RemotePorts::~RemotePorts() = default;

std::unique_ptr<tapbridge::Port> RemotePorts::Open(int robot) {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  RobotQueue& queue = impl_->robots[robot];
  SITLNET_DEMAND(queue.node >= 0 && !queue.open);
  return std::make_unique<RemotePort>(robot, &queue, &impl_->outboxes[queue.node]);
}

void RemotePorts::Receive(int node, const proto::node::NodeFrames& frames) {
  SITLNET_DEMAND(node >= 0 && node < static_cast<int>(impl_->nodes.size()));
  // All checked before any is queued: a refused message leaves nothing behind.
  if (const std::optional<std::string> broken =
          FindBrokenBound(frames, impl_->nodes[node], impl_->robot_names)) {
    throw Error(impl_->node_descriptions[node] + ": " + *broken);
  }
  for (const proto::node::FrameBatch& batch : frames.batches()) {
    RobotQueue& queue = impl_->robots[batch.robot()];
    // The node cannot know yet that the bridge closed the port (it detached the robot).
    if (!queue.open) {
      queue.dropped_closed += batch.frames_size();
      continue;
    }
    queue.frames.insert(queue.frames.end(), batch.frames().begin(), batch.frames().end());
    if (batch.read_errno() != 0) queue.read_errno = batch.read_errno();
  }
}

proto::node::NodeWrites RemotePorts::TakeWrites(int node) {
  SITLNET_DEMAND(node >= 0 && node < static_cast<int>(impl_->nodes.size()));
  return impl_->outboxes[node].Take();
}

uint64_t RemotePorts::frames_dropped_closed(int robot) const {
  return impl_->robots.at(robot).dropped_closed;
}

}  // namespace sitlnet::fleet

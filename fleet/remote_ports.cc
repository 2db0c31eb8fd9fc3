// The central host's ports of robots on node hosts: frames a node drained wait here until the
// bridge reads them, in the order the node read them; writes wait in the node's outbox.
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <deque>
#include <functional>

#include "fleet/fleet.h"
#include "fleet/node_frames_bounds.h"
#include "fleet/node_outbox.h"
#include "tapbridge/lateness_histogram.h"

namespace sitlnet::fleet {
namespace {

// What realtime pacing measures of one node's link.
struct NodeLateness {
  tapbridge::LatenessHistogram entries;
  tapbridge::LatenessHistogram writes;
};

// One robot's frames between the node's drain and the bridge's read.
struct RobotQueue {
  int node = -1;                   // Index of its node; -1: on none.
  bool open = false;               // Its port exists.
  std::deque<std::string> frames;  // Oldest first.
  std::deque<TimeNs> read_ns;      // Realtime: the node's read instant of each of `frames`.
  int read_errno = 0;              // The node's TAP read failed after `frames`.
  uint64_t dropped_closed = 0;
  int ready_fd = -1;  // Realtime: an eventfd, readable while frames or an error wait.
};

// Makes `fd` (an eventfd) readable, or not.
void SetReady(int fd, bool ready) {
  if (fd < 0) return;
  uint64_t value = 1;
  [[maybe_unused]] ssize_t n =
      ready ? write(fd, &value, sizeof value) : read(fd, &value, sizeof value);
}

class RemotePort : public tapbridge::Port {
 public:
  RemotePort(int robot, RobotQueue* queue, NodeOutbox* outbox, const clock::Timebase* realtime,
             NodeLateness* lateness)
      : robot_(robot), queue_(queue), outbox_(outbox), realtime_(realtime), lateness_(lateness) {
    queue_->open = true;
  }
  // A closed TAP drops what it held; so does a closed remote port.
  ~RemotePort() override {
    queue_->open = false;
    queue_->frames.clear();
    queue_->read_ns.clear();
    queue_->read_errno = 0;
    SetReady(queue_->ready_fd, false);
  }

  ssize_t Read(std::span<uint8_t> buffer) override {
    if (queue_->frames.empty()) {
      SetReady(queue_->ready_fd, false);  // Polls readable again on the next Receive.
      return -queue_->read_errno;         // 0: none waits.
    }
    const std::string& frame = queue_->frames.front();
    const size_t length = std::min(frame.size(), buffer.size());  // Cut, as a TAP read does.
    std::memcpy(buffer.data(), frame.data(), length);
    queue_->frames.pop_front();
    if (realtime_ != nullptr && !queue_->read_ns.empty()) {
      // The bridge enters it at its virtual now, as it enters a TAP's frame it reads now. Wall
      // time, as the bridge's own delivery lateness.
      lateness_->entries.Add(realtime_->LagNs(queue_->read_ns.front(), MonotonicNowNs()));
      queue_->read_ns.pop_front();
    }
    return static_cast<ssize_t>(length);
  }

  // Always written here: the frame reaches the TAP with the node's next NodeWrites.
  int Write(std::span<const uint8_t> frame) override {
    outbox_->Add(robot_, frame, realtime_ ? realtime_->VirtualOf(MonotonicNowNs()) : 0);
    return 0;
  }

  int fd() const override { return queue_->ready_fd; }

  // The node's TAP counts its drops; they do not come up the link yet.
  std::optional<uint64_t> KernelTxDropped() override { return std::nullopt; }

 private:
  int robot_;
  RobotQueue* queue_;
  NodeOutbox* outbox_;
  const clock::Timebase* realtime_;
  NodeLateness* lateness_;
};

}  // namespace

struct RemotePorts::Impl {
  std::vector<NodeSlice> nodes;
  std::vector<std::string> node_descriptions;  // DescribeNode, for error lines.
  std::vector<std::string> robot_names;
  std::vector<RobotQueue> robots;
  std::vector<NodeOutbox> outboxes;  // By node.
  const clock::Timebase* realtime = nullptr;
  std::vector<NodeLateness> lateness;  // By node; realtime only.

  ~Impl() {
    for (const RobotQueue& robot : robots) {
      if (robot.ready_fd >= 0) close(robot.ready_fd);
    }
  }
};

RemotePorts::RemotePorts(const Scenario& scenario, std::vector<NodeSlice> nodes,
                         const clock::Timebase* realtime)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.realtime = realtime;
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
      if (realtime != nullptr) {
        impl.robots[robot].ready_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
        if (impl.robots[robot].ready_fd < 0) throw Error(SystemErrorMessage("eventfd", errno));
      }
    }
    impl.node_descriptions.push_back(DescribeNode(scenario, nodes[node]));
  }
  impl.nodes = std::move(nodes);
  impl.outboxes.resize(impl.nodes.size());
  if (realtime != nullptr) impl.lateness.resize(impl.nodes.size());
}

RemotePorts::~RemotePorts() = default;

std::unique_ptr<tapbridge::Port> RemotePorts::Open(int robot) {
  SITLNET_DEMAND(robot >= 0 && robot < static_cast<int>(impl_->robots.size()));
  RobotQueue& queue = impl_->robots[robot];
  SITLNET_DEMAND(queue.node >= 0 && !queue.open);
  return std::make_unique<RemotePort>(robot, &queue, &impl_->outboxes[queue.node], impl_->realtime,
                                      impl_->realtime ? &impl_->lateness[queue.node] : nullptr);
}

void RemotePorts::Receive(int node, const proto::node::NodeFrames& frames) {
  SITLNET_DEMAND(node >= 0 && node < static_cast<int>(impl_->nodes.size()));
  // All checked before any is queued: a refused message leaves nothing behind.
  if (const std::optional<std::string> broken = FindBrokenBound(
          frames, impl_->nodes[node], impl_->robot_names, impl_->realtime != nullptr)) {
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
    queue.read_ns.insert(queue.read_ns.end(), batch.read_ns().begin(), batch.read_ns().end());
    if (batch.read_errno() != 0) queue.read_errno = batch.read_errno();
    SetReady(queue.ready_fd, true);
  }
  if (impl_->realtime != nullptr) {
    for (const int64_t late_ns : frames.write_late_ns()) {
      impl_->lateness[node].writes.Add(late_ns);
    }
  }
}

tapbridge::LatenessStats RemotePorts::LateEntries(int node) const {
  return impl_->realtime ? impl_->lateness.at(node).entries.Stats() : tapbridge::LatenessStats{};
}

tapbridge::LatenessStats RemotePorts::LateWrites(int node) const {
  return impl_->realtime ? impl_->lateness.at(node).writes.Stats() : tapbridge::LatenessStats{};
}

proto::node::NodeWrites RemotePorts::TakeWrites(int node) {
  SITLNET_DEMAND(node >= 0 && node < static_cast<int>(impl_->nodes.size()));
  return impl_->outboxes[node].Take();
}

uint64_t RemotePorts::frames_dropped_closed(int robot) const {
  return impl_->robots.at(robot).dropped_closed;
}

}  // namespace sitlnet::fleet

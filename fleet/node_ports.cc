#include "fleet/node_ports.h"

#include <poll.h>

#include <algorithm>

#include "fleet/node_frames_bounds.h"

namespace sitlnet::fleet {

NodePorts::NodePorts(NodeSlice slice, const OpenPort& open)
    : slice_(std::move(slice)), buffer_(kMaxNodeFrameBytes) {
  // Ascending: Find looks robots up by binary search, and Drain keeps scenario order.
  SITLNET_DEMAND(std::ranges::is_sorted(slice_.robots) &&
                 std::ranges::adjacent_find(slice_.robots) == slice_.robots.end());
  for (const int robot : slice_.robots) robots_.push_back({robot, open(robot)});
}

NodePorts::Robot* NodePorts::Find(int robot) {
  const auto found = std::ranges::lower_bound(robots_, robot, {}, &Robot::index);
  return found != robots_.end() && found->index == robot ? &*found : nullptr;
}

void NodePorts::Drain(proto::node::NodeFrames* frames) {
  frames->Clear();
  for (Robot& robot : robots_) {
    if (robot.read_failed) continue;
    proto::node::FrameBatch* batch = nullptr;
    const auto open_batch = [&] {
      if (batch == nullptr) {
        batch = frames->add_batches();
        batch->set_robot(robot.index);
      }
      return batch;
    };
    // One turn, as BridgeCore reads a local port; the buffer cuts a longer frame to
    // kMaxNodeFrameBytes, as a TAP read into it does, and the bridge still drops it as oversize.
    for (size_t turn = 0; turn < tapbridge::kMaxFramesPerRobotPerTurn; ++turn) {
      const ssize_t length = robot.port->Read(buffer_);
      if (length == 0) break;
      if (length < 0) {
        open_batch()->set_read_errno(static_cast<int>(-length));
        robot.read_failed = true;
        break;
      }
      open_batch()->add_frames(buffer_.data(), static_cast<size_t>(length));
    }
  }
}

void NodePorts::ReadUntil(TimeNs deadline_ns, const clock::Timebase& timebase,
                          proto::node::NodeFrames* frames) {
  // Each robot's batch, by its place in robots_ (one per robot: the central refuses two).
  std::vector<proto::node::FrameBatch*> batches(robots_.size(), nullptr);
  for (proto::node::FrameBatch& batch : *frames->mutable_batches()) {
    if (Robot* robot = Find(batch.robot())) batches[robot - robots_.data()] = &batch;
  }
  std::vector<pollfd> polled;
  std::vector<size_t> polled_robot;
  for (;;) {
    polled.clear();
    polled_robot.clear();
    for (size_t i = 0; i < robots_.size(); ++i) {
      const bool full =
          batches[i] != nullptr &&
          batches[i]->frames_size() >= static_cast<int>(tapbridge::kMaxFramesPerRobotPerTurn);
      if (robots_[i].read_failed || full || robots_[i].port->fd() < 0) continue;
      polled.push_back({robots_[i].port->fd(), POLLIN, 0});
      polled_robot.push_back(i);
    }
    // A Start far in the past (from a broken central) puts deadline_ns at the smallest TimeNs:
    // subtracting now from it would overflow.
    const TimeNs now_ns = MonotonicNowNs();
    const TimeNs left_ns = deadline_ns > now_ns ? deadline_ns - now_ns : 0;
    const timespec timeout{static_cast<time_t>(left_ns / kNsPerS),
                           static_cast<long>(left_ns % kNsPerS)};
    const int ready = ppoll(polled.data(), polled.size(), &timeout, nullptr);
    if (ready < 0 && errno != EINTR) throw Error(SystemErrorMessage("ppoll on the TAPs", errno));
    const TimeNs returned_ns = MonotonicNowNs();
    for (size_t p = 0; p < polled.size(); ++p) {
      const size_t i = polled_robot[p];
      Robot& robot = robots_[i];
      if (ready <= 0 || polled[p].revents == 0) {
        robot.seen_empty_wall_ns = returned_ns;
        continue;
      }
      // Its frames came after its TAP was last seen empty: the earliest they can have been
      // written, so the central's late entries bound their wait from above (not before the run).
      const TimeNs written_ns = std::max<TimeNs>(0, timebase.VirtualOf(robot.seen_empty_wall_ns));
      if (batches[i] == nullptr) {
        batches[i] = frames->add_batches();
        batches[i]->set_robot(robot.index);
      }
      proto::node::FrameBatch& batch = *batches[i];
      while (batch.frames_size() < static_cast<int>(tapbridge::kMaxFramesPerRobotPerTurn)) {
        const ssize_t length = robot.port->Read(buffer_);
        if (length == 0) {
          robot.seen_empty_wall_ns = MonotonicNowNs();
          break;
        }
        if (length < 0) {
          batch.set_read_errno(static_cast<int>(-length));
          robot.read_failed = true;
          break;
        }
        batch.add_frames(buffer_.data(), static_cast<size_t>(length));
        batch.add_read_ns(written_ns);
      }
    }
    if (left_ns == 0) return;
  }
}

void NodePorts::Write(const proto::node::NodeWrites& writes, const clock::Timebase* realtime,
                      google::protobuf::RepeatedField<int64_t>* late_ns) {
  for (const proto::node::NodeWrites::Write& write : writes.writes()) {
    if (Find(write.robot()) == nullptr) {
      throw Error("the coordinator wrote to robot " + std::to_string(write.robot()) +
                  ", which is not one of this node's");
    }
    if (write.frame_index() < 0 || write.frame_index() >= writes.frames_size()) {
      throw Error("the coordinator wrote frame " + std::to_string(write.frame_index()) + " of " +
                  std::to_string(writes.frames_size()));
    }
  }
  for (const proto::node::NodeWrites::Write& write : writes.writes()) {
    const std::string& frame = writes.frames(write.frame_index());
    Robot& robot = *Find(write.robot());
    const int written =
        robot.port->Write(std::span(reinterpret_cast<const uint8_t*>(frame.data()), frame.size()));
    if (written < 0) ++robot.write_errors;
    if (realtime != nullptr) late_ns->Add(realtime->LagNs(write.due_ns(), MonotonicNowNs()));
  }
}

uint64_t NodePorts::write_errors(int robot) const {
  const auto found = std::ranges::find(robots_, robot, &Robot::index);
  SITLNET_DEMAND(found != robots_.end());
  return found->write_errors;
}

namespace {

// The physics' context, which drains the node's ports when every command has arrived and sends
// their frames up with CommandsCollected.
class DrainingContext final : public coordinator::IterationContext {
 public:
  DrainingContext(coordinator::IterationContext& outer, NodePorts& ports)
      : outer_(outer), ports_(ports) {}
  void CommandsCollected() override {
    SITLNET_DEMAND(!reported_);
    reported_ = true;
    ports_.Drain(&frames_);
    outer_.CommandsCollectedWithPayload(frames_.SerializeAsString());
  }
  bool reported() const { return reported_; }

 private:
  coordinator::IterationContext& outer_;
  NodePorts& ports_;
  proto::node::NodeFrames frames_;
  bool reported_ = false;
};

}  // namespace

void NodeSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                 coordinator::IterationContext& context) {
  proto::node::NodeStart node_start;
  if (!node_start.ParseFromString(start.payload())) {
    throw Error("the coordinator's Start of iteration " + std::to_string(start.iteration()) +
                " carries no NodeStart that parses");
  }
  if (realtime_ != nullptr) {
    RunRealtimeIteration(start, node_start, end, context);
    return;
  }
  // Deliveries reach the robots before this iteration's states and commands.
  ports_.Write(node_start.writes());
  DrainingContext draining(context, ports_);
  physics_.RunIteration(start, end, draining);
  if (!draining.reported()) draining.CommandsCollected();
}

void NodeSimulator::RunRealtimeIteration(const proto::coord::Start& start,
                                         const proto::node::NodeStart& node_start,
                                         proto::coord::End* end,
                                         coordinator::IterationContext& context) {
  // The central sends Start k at the wall instant of its virtual start, never before: so it is
  // that instant here, less one link delay at least. Keeping the earliest such estimate, the
  // node's clock of the run is never later than the central's plus the link delay, however the
  // hosts' clocks drift; a node clock running late would hold every End late.
  const TimeNs now_ns = MonotonicNowNs();
  if (!realtime_begun_ || now_ns < realtime_->WallOf(start.start_ns())) {
    realtime_->BeginAt(start.start_ns(), now_ns);
    realtime_begun_ = true;
  }
  frames_.Clear();
  // Due during the central's previous iteration: late already, so written now.
  ports_.Write(node_start.writes(), realtime_, frames_.mutable_write_late_ns());
  const TimeNs physics_begin_ns = MonotonicNowNs();
  physics_.RunIteration(start, end, context);  // Realtime physics reports no CommandsCollected.
  const TimeNs physics_ns = MonotonicNowNs() - physics_begin_ns;
  ports_.ReadUntil(realtime_->WallOf(start.end_ns()), *realtime_, &frames_);
  frames_.SerializeToString(end->mutable_payload());
  end->set_busy_ns(std::max<TimeNs>(physics_ns, 1));  // Not the wait: ServeIterations keeps it.
}

proto::coord::Hello NodeHello(const NodeSlice& slice, coordinator::Simulator& node) {
  proto::coord::Hello hello;
  hello.mutable_robots()->Add(slice.robots.begin(), slice.robots.end());
  *hello.mutable_initial_poses() = node.InitialPoses();
  return hello;
}

}  // namespace sitlnet::fleet

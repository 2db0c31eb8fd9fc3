// The fleet's node hosts as the run's one physics connector: a round trip per node and
// iteration, frames up with CommandsCollected (lockstep) or End (realtime), deliveries down with
// the next Start.
#include "fleet/node_frames_bounds.h"
#include "fleet/node_link.h"
#include "fleet/node_poses.h"

namespace sitlnet::fleet {

FleetPhysicsConnector::FleetPhysicsConnector(const Scenario& scenario, coordinator::Pacing pacing,
                                             std::vector<std::unique_ptr<NodeLink>> nodes,
                                             RemotePorts* ports)
    : Connector("fleet", coordinator::Role::kPhysics, "the fleet's node hosts"),
      robot_count_(scenario.robots.size()),
      realtime_(pacing == coordinator::Pacing::kRealtime),
      nodes_(std::move(nodes)),
      ports_(*ports),
      writes_sent_(nodes_.size(), 0) {
  // In lockstep a second network step would drain TAPs that were drained after the commands only
  // (the NetStep round trip is not built yet).
  if (!realtime_ && scenario.network_steps_per_iteration != 1) {
    throw Error("scenario " + scenario.name +
                ": robots on node hosts in lockstep pacing need one network step per iteration "
                "for now (network_step_us equal to iteration_us; issue 35)");
  }
  for (int c = 0; c < 3 * static_cast<int>(robot_count_); ++c) initial_poses_.add_position_m(0);
  for (int c = 0; c < 4 * static_cast<int>(robot_count_); ++c) {
    initial_poses_.add_orientation_wxyz(0);
  }
  // AcceptNodes checked each node's initial poses.
  for (const std::unique_ptr<NodeLink>& node : nodes_) {
    PlacePoses(node->connector().initial_poses(), node->slice().robots, &initial_poses_);
  }
}

void FleetPhysicsConnector::Begin(const proto::coord::Start& start,
                                  const coordinator::WaitLimits& limits) {
  start_ = start;
  proto::node::NodeStart node_start;
  for (size_t node = 0; node < nodes_.size(); ++node) {
    *node_start.mutable_writes() = ports_.TakeWrites(static_cast<int>(node));
    writes_sent_[node] = node_start.writes().writes_size();
    node_start.SerializeToString(start_.mutable_payload());
    nodes_[node]->connector().Begin(start_, limits);
  }
}

bool FleetPhysicsConnector::AwaitCommandsCollected(uint64_t iteration,
                                                   const coordinator::WaitLimits& limits) {
  proto::node::NodeFrames frames;
  for (size_t node = 0; node < nodes_.size(); ++node) {
    coordinator::RemoteConnector& link = nodes_[node]->connector();
    if (!link.AwaitCommandsCollected(iteration, limits)) return false;
    if (!frames.ParseFromString(link.TakeCommandsCollectedPayload())) {
      throw Error(nodes_[node]->Describe() + ": its CommandsCollected of iteration " +
                  std::to_string(iteration) + " carries no NodeFrames that parses");
    }
    ports_.Receive(static_cast<int>(node), frames);
  }
  return true;
}

bool FleetPhysicsConnector::Finish(uint64_t iteration, proto::coord::End* end,
                                   const coordinator::WaitLimits& limits) {
  end->Clear();
  end->set_iteration(iteration);
  *end->mutable_poses() = initial_poses_;  // Every robot's place, each overwritten below.
  for (size_t index = 0; index < nodes_.size(); ++index) {
    const std::unique_ptr<NodeLink>& node = nodes_[index];
    if (!node->connector().Finish(iteration, &node_end_, limits)) return false;
    if (realtime_) ReceiveRealtimeFrames(static_cast<int>(index), iteration);
    if (const std::optional<std::string> broken =
            FindBrokenPoses(node_end_.poses(), node->slice().robots.size())) {
      throw Error(node->Describe() + ": End of iteration " + std::to_string(iteration) + ": " +
                  *broken);
    }
    PlacePoses(node_end_.poses(), node->slice().robots, end->mutable_poses());
    end->set_busy_ns(std::max(end->busy_ns(), node_end_.busy_ns()));
  }
  return true;
}

void FleetPhysicsConnector::ReceiveRealtimeFrames(int node, uint64_t iteration) {
  proto::node::NodeFrames frames;
  if (!frames.ParseFromString(node_end_.payload())) {
    throw Error(nodes_[node]->Describe() + ": its End of iteration " + std::to_string(iteration) +
                " carries no NodeFrames that parses");
  }
  // One lateness per frame written: at most what this iteration's Start took down.
  if (const std::optional<std::string> broken =
          FindBrokenWriteLateness(frames, writes_sent_[node])) {
    throw Error(nodes_[node]->Describe() + ": its End of iteration " + std::to_string(iteration) +
                " " + *broken);
  }
  ports_.Receive(node, frames);
}

std::vector<FleetLinkStats> FleetPhysicsConnector::link_stats() const {
  std::vector<FleetLinkStats> stats;
  for (const std::unique_ptr<NodeLink>& node : nodes_) {
    stats.push_back({node->slice().name, node->Describe(), node->connector().link_stats()});
  }
  return stats;
}

void FleetPhysicsConnector::Stop(const std::string& reason) {
  for (const std::unique_ptr<NodeLink>& node : nodes_) node->connector().Stop(reason);
}

}  // namespace sitlnet::fleet

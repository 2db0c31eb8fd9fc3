// The coordinator's handle on a connector in another process, over a Channel
// (AcceptConnector makes one; a fleet's node links wrap one each, fleet/).
#ifndef SITLNET_COORDINATOR_REMOTE_CONNECTOR_H_
#define SITLNET_COORDINATOR_REMOTE_CONNECTOR_H_

#include <string>

#include "coordinator/connector.h"
#include "coordinator/link_meter.h"

namespace sitlnet::coordinator {

class RemoteConnector final : public Connector {
 public:
  // `description`: see Connector; `poses`: the Hello's initial poses.
  RemoteConnector(std::string name, Role role, Channel channel, proto::coord::Poses poses,
                  std::string description = {});

  const proto::coord::Poses& initial_poses() const override { return poses_; }
  void Begin(const proto::coord::Start& start, const WaitLimits& limits) override;
  bool AwaitCommandsCollected(uint64_t iteration, const WaitLimits& limits) override;
  bool Finish(uint64_t iteration, proto::coord::End* end, const WaitLimits& limits) override;
  void Stop(const std::string& reason) override;

  // The payload of the CommandsCollected AwaitCommandsCollected just received (empty when an
  // End came in its place); left empty here.
  std::string TakeCommandsCollectedPayload();

  // The link's round trips so far: START sent until END read, and the bytes each way.
  LinkStats link_stats() const { return meter_.Stats(); }

 private:
  std::string Explain(const TransportError& e) const;
  bool ReceiveExpected(uint64_t iteration, const char* what, const WaitLimits& limits);
  Error Unexpected(uint64_t iteration, const char* what) const;

  // Longest wait for the END of an interrupted iteration at Stop.
  static constexpr TimeNs kDrainTimeoutNs = 2 * kNsPerS;

  Channel channel_;
  proto::coord::Poses poses_;
  bool outstanding_ = false;  // START sent, END not yet received.
  bool early_end_ = false;    // END arrived instead of CommandsCollected; it is in in_.
  uint64_t outstanding_iteration_ = 0;
  proto::coord::CoordinatorMessage out_;
  proto::coord::CoordinatorMessage in_;
  LinkMeter meter_;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_REMOTE_CONNECTOR_H_

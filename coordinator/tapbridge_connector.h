// Network connector over tapbridge in lockstep pacing: each iteration moves
// the stations to the poses of START, then BridgeCore::StepLockstep(end_ns)
// drains every robot's TAP, enters the frames at seeded instants of the
// iteration in robot order, runs the medium to end_ns and writes every
// delivery due by then to the destination TAPs (docs/tapbridge.md). With
// CommandsCollected gating (docs/coordinator.md) every frame a robot wrote
// before its command k is in its TAP when StepLockstep runs for iteration k.
// Realtime pacing does not use this connector: the medium daemon paces
// itself against the wall clock and takes positions on its control socket.
#ifndef SITLNET_COORDINATOR_TAPBRIDGE_CONNECTOR_H_
#define SITLNET_COORDINATOR_TAPBRIDGE_CONNECTOR_H_

#include "coordinator/connector.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::coordinator {

class TapBridgeSimulator final : public Simulator {
 public:
  // `bridge` (not owned) must be attached (AttachAll) and outlive this.
  explicit TapBridgeSimulator(tapbridge::BridgeCore* bridge) : bridge_(*bridge) {}
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  tapbridge::BridgeCore& bridge_;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_TAPBRIDGE_CONNECTOR_H_

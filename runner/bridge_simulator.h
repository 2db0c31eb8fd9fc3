// The network side of `sitlnet run`: a coordinator Simulator over the
// tapbridge (robots' TAPs + the mac_phy_sim medium). Each iteration moves the
// stations to the poses physics reported, then
//  - realtime: runs the bridge's event loop until the wall instant of the
//    iteration's end (deliveries are written at their own wall instants);
//  - lockstep: steps the medium δ_net by δ_net, draining the TAPs first.
#ifndef SITLNET_RUNNER_BRIDGE_SIMULATOR_H_
#define SITLNET_RUNNER_BRIDGE_SIMULATOR_H_

#include "coordinator/connector.h"
#include "coordinator/pacing.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

class BridgeSimulator final : public coordinator::Simulator {
 public:
  // `bridge` must be attached and outlive this.
  BridgeSimulator(const Scenario& scenario, tapbridge::BridgeCore* bridge,
                  coordinator::Pacing pacing, double realtime_factor);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;

 private:
  void MoveStations(const proto::coord::Poses& poses);

  tapbridge::BridgeCore& bridge_;
  coordinator::Pacing pacing_;
  clock::Timebase timebase_;  // Begun at the first realtime iteration.
  TimeNs network_step_ns_;
  tapbridge::EventLoop loop_;
  bool started_ = false;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_BRIDGE_SIMULATOR_H_

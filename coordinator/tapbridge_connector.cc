#include "coordinator/tapbridge_connector.h"

#include <algorithm>

namespace sitlnet::coordinator {

void TapBridgeSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                      IterationContext& context) {
  const proto::coord::Poses& poses = start.poses();
  const int n = std::min(bridge_.robot_count(), poses.position_m_size() / 3);
  for (int i = 0; i < n; ++i) {
    bridge_.SetPosition(i, poses.position_m(3 * i), poses.position_m(3 * i + 1),
                        poses.position_m(3 * i + 2));
  }
  bridge_.StepLockstep(start.end_ns());
}

}  // namespace sitlnet::coordinator

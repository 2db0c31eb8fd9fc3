#include "physics_mujoco/robot_link.h"

#include <algorithm>
#include <limits>

namespace sitlnet::physics {

std::vector<std::unique_ptr<RobotLink>> MakeRobotLinks(const RobotLinkSetup& setup) {
  // The protocols, in the order a robot's links are served and its silent autopilots reported.
  using Maker = std::unique_ptr<RobotLink> (*)(const RobotLinkSetup&);
  static constexpr Maker kProtocols[] = {MakeNativeLink, MakeArduPilotJsonLink, MakePx4Link};
  std::vector<std::unique_ptr<RobotLink>> links;
  for (int kind = 0; kind < static_cast<int>(std::size(kProtocols)); ++kind) {
    if (std::unique_ptr<RobotLink> link = kProtocols[kind](setup)) {
      link->robot = setup.robot->robot;
      link->kind = kind;
      links.push_back(std::move(link));
    }
  }
  return links;
}

int StepsUntil(TimeNs due_ns, TimeNs now_ns, TimeNs step_ns) {
  return static_cast<int>(std::clamp<TimeNs>((due_ns - now_ns + step_ns - 1) / step_ns, 1,
                                             std::numeric_limits<int>::max()));
}

}  // namespace sitlnet::physics

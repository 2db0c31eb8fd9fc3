// `status`: what exists now for each robot of a scenario, read from the
// kernel (links, addresses, processes), not from memory.
#include <memory>

#include "nns/nns_internal.h"

namespace sitlnet::nns {

std::vector<RobotStatus> Status(const ScenarioState& state) {
  std::vector<RobotStatus> result;
  std::vector<internal::NsId> namespaces;
  std::vector<size_t> robot_of_namespace;
  // The root sides of the ctl links are in the scenario's ctl namespace.
  std::unique_ptr<internal::RouteSocket> ctl;
  if (NetnsExists(CtlNetnsName(state.name))) {
    try {
      ScopedNetns enter(CtlNetnsName(state.name));
      ctl = std::make_unique<internal::RouteSocket>();
    } catch (const Error&) {
      // Not a namespace (an `up` killed half-way): its veths show as missing.
    }
  }
  for (const OwnedRobot& robot : state.robots) {
    RobotStatus status;
    status.robot = robot;
    status.root_veth_present = ctl && internal::LinkIndex(*ctl, robot.root_veth) != 0;
    internal::NsId id;
    if (internal::StatNs(NetnsPath(robot.netns), &id)) {
      status.netns_present = true;
      namespaces.push_back(id);
      robot_of_namespace.push_back(result.size());
      std::unique_ptr<internal::RouteSocket> inside;
      {
        ScopedNetns enter(robot.netns);
        inside = std::make_unique<internal::RouteSocket>();
      }
      status.links = internal::DumpLinks(*inside);
    }
    result.push_back(std::move(status));
  }
  std::vector<int> owner;
  const std::vector<ProcessInfo> processes = internal::ScanProcesses(namespaces, &owner);
  for (size_t i = 0; i < processes.size(); ++i) {
    result[robot_of_namespace[owner[i]]].processes.push_back(processes[i]);
  }
  return result;
}

}  // namespace sitlnet::nns

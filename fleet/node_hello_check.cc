#include "fleet/node_hello_check.h"

#include <algorithm>

#include "coordinator/connector.h"
#include "fleet/node_poses.h"

namespace sitlnet::fleet {
namespace {

// Robots a refusal names, at most: a peer's claim may list millions, and the refusal is one line
// of the central's log and one Error message to the peer.
constexpr size_t kMaxNamedRobots = 8;

// "c, d"; an index outside the scenario as a number; past kMaxNamedRobots, "and N more".
std::string RobotNames(const Scenario& scenario, const std::vector<int>& robots) {
  std::string names;
  for (size_t i = 0; i < robots.size() && i < kMaxNamedRobots; ++i) {
    const int robot = robots[i];
    if (!names.empty()) names += ", ";
    names += robot >= 0 && robot < static_cast<int>(scenario.robots.size())
                 ? scenario.robots[robot].name
                 : std::to_string(robot);
  }
  if (robots.size() > kMaxNamedRobots) {
    names += " and " + std::to_string(robots.size() - kMaxNamedRobots) + " more";
  }
  return names.empty() ? "none" : names;
}

}  // namespace

std::string RefuseNodeHello(const Scenario& scenario, const std::vector<NodeSlice>& nodes,
                            const proto::coord::Hello& hello) {
  const std::string name = coordinator::PrintableName(hello.connector_name());
  const auto node = std::ranges::find(nodes, hello.connector_name(), &NodeSlice::name);
  if (node == nodes.end()) {
    std::string names;
    for (const NodeSlice& slice : nodes) names += (names.empty() ? "" : ", ") + slice.name;
    return "node '" + name + "' is not one of this run's nodes (" + names + ")";
  }
  const std::vector<int> claimed(hello.robots().begin(), hello.robots().end());
  if (claimed != node->robots) {
    return "node '" + name + "' claims robots " + RobotNames(scenario, claimed) +
           ", but the scenario gives it " + RobotNames(scenario, node->robots) +
           " (another scenario or --node?)";
  }
  if (const std::optional<std::string> broken =
          FindBrokenPoses(hello.initial_poses(), node->robots.size())) {
    return DescribeNode(scenario, *node) + ": initial poses: " + *broken;
  }
  return "";
}

}  // namespace sitlnet::fleet

#include "fleet/fleet.h"

namespace sitlnet::fleet {

std::string DescribeNode(const Scenario& scenario, const NodeSlice& node) {
  std::string robots;
  for (const int robot : node.robots) {
    if (!robots.empty()) robots += ", ";
    robots += scenario.robots.at(robot).name;
  }
  return "node '" + node.name + "' (robots " + robots + ")";
}

}  // namespace sitlnet::fleet

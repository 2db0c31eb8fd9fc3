#include "coordinator/coordinator.h"
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

uint64_t NodeScenarioHash(const Scenario& scenario) {
  Scenario copy = scenario;
  copy.spec.mutable_timing()->clear_duration_ms();
  return coordinator::ScenarioHash(copy);
}

}  // namespace sitlnet::fleet

// What a host that runs robots (`sitlnet run` on one host, `sitlnet node` on a node host) needs
// before and around them: the host's grants, and the robots' namespaces while the run lives.
#ifndef SITLNET_RUNNER_ROBOT_HOST_H_
#define SITLNET_RUNNER_ROBOT_HOST_H_

#include <string>
#include <vector>

#include "scenario/scenario.h"

namespace sitlnet::runner {

// What the host must grant before anything of the run exists: privileges, the scenario's name
// free, this process as the robots' subreaper, enough open files for `robots` robots. Throws
// Error (PrivilegeError for privileges).
void PrepareRobotHost(const Scenario& scenario, size_t robots);

// Brings the robots `robots` (empty: all) of the scenario up, registering this process as its run
// (another run of it is refused, not torn down), and tears them down however the run ends.
class ScenarioNamespaces {
 public:
  ScenarioNamespaces(const Scenario& scenario, const std::vector<int>& robots = {});
  ~ScenarioNamespaces();
  ScenarioNamespaces(const ScenarioNamespaces&) = delete;
  ScenarioNamespaces& operator=(const ScenarioNamespaces&) = delete;

 private:
  std::string name_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ROBOT_HOST_H_

#include "runner/robot_host.h"

#include <sys/prctl.h>

#include <cstdio>

#include "nns/nns.h"

namespace sitlnet::runner {

void PrepareRobotHost(const Scenario& scenario, size_t robots) {
  nns::RequirePrivileges();
  nns::RefuseIfInUse(scenario.name);  // Before the run folder: a refused run leaves nothing.
  // A sandboxed robot's init outlives bubblewrap by a moment (docs/security.md); as the
  // subreaper, this process reaps it, so its CPU time (the image's) is in RUSAGE_CHILDREN.
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  // Per robot: its TAP, physics socket, log, pidfds and the medium's and bridge's own; 64 for
  // the rest (outputs, sockets, pipes). Debian's default soft limit (1024) ran out near 250.
  constexpr uint64_t kOpenFilesPerRobot = 8;
  constexpr uint64_t kOpenFilesBase = 64;
  RaiseOpenFileLimit(kOpenFilesBase + kOpenFilesPerRobot * robots,
                     "a run of " + std::to_string(robots) + " robots");
}

ScenarioNamespaces::ScenarioNamespaces(const Scenario& scenario, const std::vector<int>& robots)
    : name_(scenario.name) {
  nns::UpOptions up_options;
  up_options.register_caller_as_run = true;
  up_options.robots = robots;
  nns::Up(scenario, up_options);
}

ScenarioNamespaces::~ScenarioNamespaces() {
  try {
    nns::Down(name_);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "sitlnet: down %s: %s\n", name_.c_str(), error.what());
  }
}

}  // namespace sitlnet::runner

// `sitlnet exec ROBOT -- CMD ARGS...`: replaces itself with CMD inside the
// robot's network namespace, so the exit status and signals are CMD's own.
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "nns/nns.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kExecHelp =
    "usage: sitlnet exec [--scenario NAME] ROBOT [--] CMD [ARGS...]\n"
    "\n"
    "Runs CMD in the network namespace of ROBOT, which is a robot name when it\n"
    "is unique among the scenarios that are up, or <scenario>-<robot> (the\n"
    "namespace name), or a robot name with --scenario. Environment added:\n"
    "  SITLNET_SCENARIO      scenario name\n"
    "  SITLNET_ROBOT         robot name\n"
    "  SITLNET_ROBOT_INDEX   robot index in the scenario, from 0\n"
    "  SITLNET_PHYSICS_ADDR  <root side of ctl0>:<physics port>, the physics server\n"
    "Only the network namespace changes (no mount namespace, unlike ip netns exec).\n"
    "\n"
    "exit codes: CMD's own status (128+N if killed by signal N, as a shell shows\n"
    "it); 125 sitlnet failed before running CMD (unknown robot, privileges,\n"
    "usage); 126 CMD cannot be executed; 127 CMD not found.\n";

// `env`'s convention, so that CMD's own 1..3 stay distinguishable.
constexpr int kExitExecFailed = 125;
constexpr int kExitCannotExecute = 126;
constexpr int kExitNotFound = 127;

}  // namespace

int RunExecCommand(int argc, char** argv) {
  if (WantsHelp(argc, argv)) {
    std::fputs(kExecHelp, stdout);
    return kExitOk;
  }
  std::string scenario_name;
  int i = 1;
  if (i + 1 < argc && !std::strcmp(argv[i], "--scenario")) {
    scenario_name = argv[i + 1];
    i += 2;
  }
  if (i >= argc) {
    std::fputs(kExecHelp, stderr);
    return kExitExecFailed;
  }
  const std::string robot = argv[i++];
  if (i < argc && !std::strcmp(argv[i], "--")) ++i;
  if (i >= argc) {
    std::fputs(kExecHelp, stderr);
    return kExitExecFailed;
  }
  char** command = argv + i;

  const int status = ReportErrors("exec", kExitExecFailed, [&] {
    nns::RequirePrivileges();
    std::vector<nns::ScenarioState> scenarios;
    for (const std::string& name : nns::ListScenarios()) {
      if (auto state = nns::ReadScenarioState(name)) scenarios.push_back(std::move(*state));
    }
    const nns::RobotRef ref = nns::ResolveRobot(scenarios, robot, scenario_name);
    // This process is single-threaded, so setns moves all of it; the fd is
    // close-on-exec and does not leak into CMD.
    nns::UniqueFd netns = nns::OpenNetns(ref.robot.netns);
    if (setns(netns.get(), CLONE_NEWNET) != 0) {
      throw Error(SystemErrorMessage("enter namespace \"" + ref.robot.netns + "\"", errno));
    }
    setenv("SITLNET_SCENARIO", ref.scenario.name.c_str(), 1);
    setenv("SITLNET_ROBOT", ref.robot.name.c_str(), 1);
    setenv("SITLNET_ROBOT_INDEX", std::to_string(ref.robot.index).c_str(), 1);
    setenv("SITLNET_PHYSICS_ADDR", ref.scenario.PhysicsAddress(ref.robot).c_str(), 1);
    return kExitOk;
  });
  if (status != kExitOk) return status;
  execvp(command[0], command);
  const int err = errno;
  // EPERM from exec of an existing file: most often a program with file capabilities (Debian's
  // ping: cap_net_raw) outside this process's bounding set, e.g. in a container without them.
  const char* hint = err == EPERM ? " (a program with file capabilities, such as ping, cannot "
                                    "run when they are outside the bounding set: "
                                    "docs/security.md)"
                                  : "";
  std::fprintf(stderr, "sitlnet exec: run \"%s\": %s%s\n", command[0], std::strerror(err), hint);
  return err == ENOENT ? kExitNotFound : kExitCannotExecute;
}

}  // namespace sitlnet::cli

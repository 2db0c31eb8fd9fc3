// `sitlnet exec ROBOT -- CMD ARGS...`: replaces itself with CMD inside the
// robot's network namespace, so the exit status and signals are CMD's own.
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "nns/nns.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kExecFooter =
    "Runs CMD in the network namespace of ROBOT, which is a robot name when it\n"
    "is unique among the scenarios that are up, or <scenario>-<robot> (the\n"
    "namespace name), or a robot name with --scenario. Environment added:\n"
    "  SITLNET_SCENARIO      scenario name\n"
    "  SITLNET_ROBOT         robot name\n"
    "  SITLNET_ROBOT_INDEX   robot index in the scenario, from 0\n"
    "  SITLNET_PHYSICS_ADDR  <root side of ctl0>:<physics port>, the physics server\n"
    "Only the network namespace changes (no mount namespace, unlike ip netns exec).\n"
    "Everything after ROBOT is CMD and its arguments, options included; a -- before\n"
    "CMD is optional. An ambiguous robot name is refused with the candidates.\n"
    "\n"
    "exit codes (env's convention, so that CMD's own stay visible): CMD's own\n"
    "status (128+N if killed by signal N, as a shell shows it); 125 sitlnet failed\n"
    "before running CMD (unknown or ambiguous robot, privileges, usage); 126 CMD\n"
    "cannot be executed; 127 CMD not found.";

// `env`'s convention, so that CMD's own 1..3 stay distinguishable.
constexpr int kExitExecFailed = 125;
constexpr int kExitCannotExecute = 126;
constexpr int kExitNotFound = 127;

// Enters ROBOT's network namespace and replaces this process with `command` (argv order).
int Exec(const std::string& scenario_name, const std::string& robot,
         std::vector<std::string> command) {
  if (!command.empty() && command.front() == "--") command.erase(command.begin());
  if (command.empty()) {
    std::fprintf(stderr, "sitlnet exec: CMD is required (sitlnet exec --help)\n");
    return kExitExecFailed;
  }
  const int status = ReportErrors("exec", kExitExecFailed, [&] {
    nns::RequirePrivileges();
    std::vector<nns::ScenarioState> scenarios;
    for (const std::string& name : nns::ListScenarios()) {
      if (auto state = nns::ReadScenarioState(name)) scenarios.push_back(std::move(*state));
    }
    const nns::RobotRef ref = nns::ResolveRobot(scenarios, robot, scenario_name);
    // This process is single-threaded, so setns moves all of it; the fd is
    // close-on-exec and does not leak into CMD.
    UniqueFd netns = nns::OpenNetns(ref.robot.netns);
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
  std::vector<char*> argv;
  for (std::string& arg : command) argv.push_back(arg.data());
  argv.push_back(nullptr);
  execvp(argv[0], argv.data());
  const int err = errno;
  // EPERM from exec of an existing file: most often a program with file capabilities (Debian's
  // ping: cap_net_raw) outside this process's bounding set, e.g. in a container without them.
  const char* hint = err == EPERM ? " (a program with file capabilities, such as ping, cannot "
                                    "run when they are outside the bounding set: "
                                    "docs/security.md)"
                                  : "";
  std::fprintf(stderr, "sitlnet exec: run \"%s\": %s%s\n", argv[0], std::strerror(err), hint);
  return err == ENOENT ? kExitNotFound : kExitCannotExecute;
}

}  // namespace

Command AddExecCommand(CLI::App& sitlnet) {
  CLI::App* exec = sitlnet.add_subcommand("exec", "run a program inside a robot's namespace");
  exec->footer(kExecFooter);
  struct Arguments {
    std::string scenario;
    std::string robot;
    std::vector<std::string> command;
  };
  auto arguments = std::make_shared<Arguments>();
  exec->add_option("--scenario", arguments->scenario, "the scenario ROBOT belongs to")
      ->type_name("NAME");
  exec->add_option("ROBOT", arguments->robot,
                   "a robot name, unique among the scenarios that are up, or <scenario>-<robot>")
      ->required();
  exec->add_option("CMD", arguments->command, "the program and its arguments")->required();
  // After ROBOT every argument is CMD's, even one that looks like an option of ours.
  exec->positionals_at_end();
  return {exec,
          [arguments] { return Exec(arguments->scenario, arguments->robot, arguments->command); },
          kExitExecFailed};
}

}  // namespace sitlnet::cli

// `sitlnet status [SCENARIO]`: robots, their devices and processes, as the
// kernel sees them now.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "nns/nns.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kStatusFooter =
    "For every scenario that is up (or the one named): each robot, whether its\n"
    "namespace and root-side veth exist, the devices inside with state, MAC,\n"
    "IPv4 addresses and txqueuelen, and the processes running inside\n"
    "(pid:command). Everything is read from the kernel at that moment.\n"
    "\n"
    "exit codes: 0 ok (also when nothing is up), 1 the named scenario is not up\n"
    "or a read failed, 2 usage, 3 missing privileges.";

void PrintScenario(const nns::ScenarioState& state) {
  std::printf("scenario %s (%zu robots, physics port %d, from %s)\n", state.name.c_str(),
              state.robots.size(), state.physics_port, state.source_path.c_str());
  for (const nns::RobotStatus& robot : nns::Status(state)) {
    std::printf("  robot %s #%d: namespace %s %s, root veth %s %s %s\n", robot.robot.name.c_str(),
                robot.robot.index, robot.robot.netns.c_str(),
                robot.netns_present ? "present" : "MISSING", robot.robot.root_veth.c_str(),
                FormatIpv4(robot.robot.ctl_root_address).c_str(),
                robot.root_veth_present ? "present" : "MISSING");
    for (const nns::LinkInfo& link : robot.links) {
      std::string addresses;
      for (const std::string& address : link.ipv4) addresses.append(" ").append(address);
      std::printf("    %-6s %-8s %-4s %s txqueuelen %d%s\n", link.name.c_str(), link.kind.c_str(),
                  link.up ? "up" : "down", link.mac.c_str(), link.txqueuelen, addresses.c_str());
    }
    std::string processes;
    for (const nns::ProcessInfo& process : robot.processes) {
      processes.append(" ").append(std::to_string(process.pid)).append(":").append(process.command);
    }
    std::printf("    processes:%s\n", processes.empty() ? " none" : processes.c_str());
  }
}

int Status(const std::string& only) {
  return ReportErrors("status", kExitFailure, [&] {
    nns::RequirePrivileges();
    std::vector<std::string> names = nns::ListScenarios();
    if (!only.empty()) {
      const std::optional<nns::ScenarioState> state = nns::ReadScenarioState(only);
      if (!state) throw Error("scenario \"" + only + "\" is not up");
      PrintScenario(*state);
      return kExitOk;
    }
    if (names.empty()) std::printf("no scenario is up\n");
    for (const std::string& name : names) {
      if (auto state = nns::ReadScenarioState(name)) PrintScenario(*state);
    }
    return kExitOk;
  });
}

}  // namespace

Command AddStatusCommand(CLI::App& sitlnet) {
  CLI::App* status = sitlnet.add_subcommand("status", "show robots, devices and processes");
  status->footer(kStatusFooter);
  auto name = std::make_shared<std::string>();
  status->add_option("SCENARIO_NAME", *name, "only this scenario (default: every one that is up)");
  return {status, [name] { return Status(*name); }};
}

}  // namespace sitlnet::cli

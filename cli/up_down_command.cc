// `sitlnet up SCENARIO` and `sitlnet down SCENARIO|--all`.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "nns/nns.h"
#include "scenario/scenario.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kUpDescription =
    "Creates, for every robot of the scenario, the namespace <scenario>-<robot>\n"
    "(usable with `ip netns exec`) holding lo, wlan0 (a persistent TAP for the\n"
    "simulated medium) and ctl0 (a veth to the scenario's ctl namespace\n"
    "<scenario>.ctl, root end <scenario>-c<index>, /30 addresses, for the physics\n"
    "channel); no default route. A scenario that is running (a live sitlnet run,\n"
    "medium or physics of it) is refused, naming each; leftovers of the same\n"
    "scenario (a previous up, a crash) are removed first. Namespaces or devices\n"
    "with our names that this scenario did not create, and subnets that overlap a\n"
    "host route, are refused before anything is touched (two scenarios up at once\n"
    "need different ctl_subnets).\n"
    "A failure half-way removes everything created. Details: docs/nns.md.\n"
    "Prints one line: up <scenario>: N robots (<first> .. <last>) in T ms; state in\n"
    "/run/sitlnet/<scenario>.\n";

constexpr const char* kUpExitCodes =
    "exit codes: 0 up, 1 failed or refused (nothing left behind), 2 usage or bad\n"
    "scenario file, 3 missing privileges.";

constexpr const char* kDownDescription =
    "Stops every process in the scenario's namespaces (SIGTERM, then SIGKILL\n"
    "after 2 s), deletes the root-side veths, unmounts and removes the\n"
    "namespaces and the state in /run/sitlnet/<scenario>. Idempotent; works\n"
    "after a crash or kill -9 of everything. --all does it for every scenario\n"
    "that has a state. Only objects listed in the scenario's state are touched.\n"
    "The containers of its OCI robot images are removed too (docs/containers.md).\n";

constexpr const char* kDownExitCodes =
    "exit codes: 0 done (also when nothing was up), 1 failed, 2 usage,\n"
    "3 missing privileges.";

// Test hook (docs/nns.md): hold forever after N robots, so that a test can
// kill -9 `up` at a known point. Never set outside tests.
std::optional<int> HoldAfterRobots() {
  const char* value = std::getenv("SITLNET_TEST_HOLD_AFTER_ROBOTS");
  if (value == nullptr || *value == '\0') return std::nullopt;
  return std::atoi(value);
}

void PrintReport(const std::string& name, const nns::DownReport& report) {
  std::printf("down %s: %d namespaces, %d links removed; %d processes terminated, %d killed",
              name.c_str(), report.namespaces_removed, report.links_removed,
              report.processes_terminated, report.processes_killed);
  if (report.containers_removed > 0) {
    std::printf("; %d containers removed", report.containers_removed);
  }
  std::printf("\n");
}

int Up(const std::string& path) {
  const int privileges = ReportErrors("up", kExitFailure, [] {
    nns::RequirePrivileges();
    return kExitOk;
  });
  if (privileges != kExitOk) return privileges;
  std::optional<Scenario> scenario;
  const int loaded = ReportErrors("up", kExitUsage, [&] {
    scenario = LoadScenarioFile(path);
    return kExitOk;
  });
  if (loaded != kExitOk) return loaded;
  return ReportErrors("up", kExitFailure, [&] {
    nns::UpOptions options;
    if (const std::optional<int> hold = HoldAfterRobots()) {
      options.on_robot_done = [hold](int robots_done) {
        if (robots_done != *hold) return;
        std::fprintf(stderr, "sitlnet up: holding after robot %d\n", robots_done);
        std::fflush(stderr);
        for (;;) pause();
      };
    }
    const TimeNs start_ns = MonotonicNowNs();
    nns::Up(*scenario, options);
    const TimeNs elapsed_ns = MonotonicNowNs() - start_ns;
    std::printf("up %s: %zu robots (%s .. %s) in %.1f ms; state in %s/%s\n", scenario->name.c_str(),
                scenario->robots.size(), scenario->robots.front().netns.c_str(),
                scenario->robots.back().netns.c_str(), static_cast<double>(elapsed_ns) / kNsPerMs,
                nns::kStateDir, scenario->name.c_str());
    return kExitOk;
  });
}

int Down(const std::string& target, bool all) {
  return ReportErrors("down", kExitFailure, [&] {
    nns::RequirePrivileges();
    if (all) {
      for (const std::string& name : nns::ListScenarios()) PrintReport(name, nns::Down(name));
      return kExitOk;
    }
    // A scenario file is accepted too: `down` what `up` of that file created.
    std::string name = target;
    if (target.find('/') != std::string::npos || target.ends_with(".textproto")) {
      name = LoadScenarioFile(target).name;
    }
    PrintReport(name, nns::Down(name));
    return kExitOk;
  });
}

}  // namespace

Command AddUpCommand(CLI::App& sitlnet) {
  CLI::App* up =
      sitlnet.add_subcommand("up", "create the robots of a scenario (namespaces, devices)");
  up->footer(std::string(kUpDescription) + "\n" + kUpExitCodes);
  auto path = std::make_shared<std::string>();
  up->add_option("SCENARIO", *path, "the scenario file")->required();
  return {up, [path] { return Up(*path); }};
}

Command AddDownCommand(CLI::App& sitlnet) {
  CLI::App* down = sitlnet.add_subcommand("down", "remove everything a scenario created");
  down->footer(std::string(kDownDescription) + "\n" + kDownExitCodes);
  auto target = std::make_shared<std::string>();
  auto all = std::make_shared<bool>(false);
  CLI::Option* scenario = down->add_option(
      "SCENARIO", *target, "the name of a scenario, or its file (down what `up` of it created)");
  CLI::Option* every = down->add_flag("--all", *all, "every scenario that has a state");
  scenario->excludes(every);
  down->require_option(1);  // SCENARIO or --all.
  return {down, [target, all] { return Down(*target, *all); }};
}

}  // namespace sitlnet::cli

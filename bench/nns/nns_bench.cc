// Wall time of nns::Up and nns::Down for 1, 16, 64 and 128 robots (medians
// of --runs runs). Needs root. Not a test: prints a markdown table for
// docs/performance.md. --processes starts one `sleep` per robot after up, so
// that down also measures SIGTERM delivery and the wait on pidfds.
// Usage: nns_bench [--runs N] [--robots 1,16,64,128] [--processes]
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "nns/nns.h"

namespace sitlnet::nns {
namespace {

Scenario BenchScenario(int robots) {
  // Subnets away from the 10.77/10.78 defaults so that a scenario someone
  // else has up does not clash.
  std::string text = "name: \"nbench" + std::to_string(robots) + "\"\n";
  for (int i = 0; i < robots; ++i) text += "robot { name: \"r" + std::to_string(i) + "\" }\n";
  text += "addresses { wlan_subnet: \"10.254.0.0/24\" ctl_subnet: \"10.253.0.0/16\" }\n";
  return LoadScenarioText(text, "nns_bench");
}

// One `sleep` per robot, started inside its namespace (as `sitlnet exec`).
std::vector<pid_t> StartSleepers(const Scenario& scenario) {
  std::vector<pid_t> pids;
  for (const RobotPlan& robot : scenario.robots) {
    UniqueFd netns = OpenNetns(robot.netns);
    const pid_t pid = fork();
    if (pid == 0) {
      if (setns(netns.get(), CLONE_NEWNET) != 0) _exit(125);
      execlp("sleep", "sleep", "1000", nullptr);
      _exit(127);
    }
    pids.push_back(pid);
  }
  return pids;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

int Main(int argc, char** argv) {
  int runs = 5;
  bool processes = false;
  std::vector<int> sizes = {1, 16, 64, 128};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) {
      runs = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--processes")) {
      processes = true;
    } else if (!std::strcmp(argv[i], "--robots") && i + 1 < argc) {
      sizes.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');)
        sizes.push_back(std::atoi(item.c_str()));
    } else {
      std::fprintf(stderr, "usage: nns_bench [--runs N] [--robots 1,16,64,128] [--processes]\n");
      return 2;
    }
  }
  if (auto missing = MissingPrivileges()) {
    std::fprintf(stderr, "nns_bench: %s\n", missing->c_str());
    return 3;
  }
  std::printf(
      "| robots | up median (ms) | up min..max | down median (ms) | down min..max | runs |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  for (int robots : sizes) {
    const Scenario scenario = BenchScenario(robots);
    std::vector<double> up_ms, down_ms;
    for (int run = 0; run < runs; ++run) {
      const TimeNs t0 = MonotonicNowNs();
      Up(scenario);
      std::vector<pid_t> sleepers;
      if (processes) sleepers = StartSleepers(scenario);
      // Not timed: wait until every sleeper runs inside (its exec is done),
      // so that down has processes to find.
      for (const RobotPlan& robot : scenario.robots) {
        while (processes && ProcessesInNetns(robot.netns).empty()) sched_yield();
      }
      const TimeNs t1 = MonotonicNowNs();
      const DownReport report = Down(scenario.name);
      const TimeNs t2 = MonotonicNowNs();
      for (pid_t pid : sleepers) waitpid(pid, nullptr, 0);
      if (processes && report.processes_terminated != robots) {
        std::fprintf(stderr, "nns_bench: %d processes terminated, expected %d\n",
                     report.processes_terminated, robots);
        return 1;
      }
      // The robots' namespaces and the scenario's ctl namespace; a root-side veth per robot.
      if (report.namespaces_removed != robots + 1 || report.links_removed != robots) {
        std::fprintf(stderr,
                     "nns_bench: down removed %d namespaces and %d links, expected %d and %d\n",
                     report.namespaces_removed, report.links_removed, robots + 1, robots);
        return 1;
      }
      up_ms.push_back(static_cast<double>(t1 - t0) / kNsPerMs);
      down_ms.push_back(static_cast<double>(t2 - t1) / kNsPerMs);
    }
    std::printf("| %d | %.1f | %.1f..%.1f | %.1f | %.1f..%.1f | %d |\n", robots, Median(up_ms),
                *std::min_element(up_ms.begin(), up_ms.end()),
                *std::max_element(up_ms.begin(), up_ms.end()), Median(down_ms),
                *std::min_element(down_ms.begin(), down_ms.end()),
                *std::max_element(down_ms.begin(), down_ms.end()), runs);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace sitlnet::nns

int main(int argc, char** argv) {
  try {
    return sitlnet::nns::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nns_bench: %s\n", e.what());
    return 1;
  }
}

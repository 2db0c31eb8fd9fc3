#include "runner/robot_stop.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

namespace sitlnet::runner {
namespace {

// VmHWM of a process in KiB (0 if unreadable): its peak resident set since exec.
int64_t PeakRssKib(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::atoll(line.c_str() + 6);
  }
  return 0;
}

}  // namespace

void StopRobots(std::vector<RobotSlot>* robots,
                std::vector<std::unique_ptr<images::RobotProcess>>* clock_publishers,
                RunReport* report) {
  // SIGTERM to every image first, then wait for each: images may need up to
  // their receive timeout to notice (flocker: 1 s), so stopping them one
  // after the other took 41 s for 64 robots.
  std::vector<int64_t> rss_kib;
  for (RobotSlot& robot : *robots) {
    if (robot.process && !robot.exit_status && !robot.process->PollExit()) {
      const int64_t peak = PeakRssKib(robot.process->CommandPid());
      if (peak > 0) rss_kib.push_back(peak);
      robot.process->RequestStop();
    }
  }
  if (!rss_kib.empty()) {
    std::sort(rss_kib.begin(), rss_kib.end());
    report->robot_max_rss_kib = rss_kib.back();
    report->robot_median_rss_kib = rss_kib[rss_kib.size() / 2];
  }
  for (RobotSlot& robot : *robots) {
    if (robot.process && !robot.exit_status) robot.process->Stop();
    // Whatever the robot left behind (a process that left its session or namespaces) is in its
    // cgroup: killed, then what all of them used is read.
    if (robot.cgroup) {
      robot.cgroup->KillAll();
      robot.usage = robot.cgroup->Usage();
    }
  }
  for (auto& publisher : *clock_publishers) publisher->RequestStop();
  clock_publishers->clear();  // Stop() each: it ends at SIGTERM.
}

}  // namespace sitlnet::runner

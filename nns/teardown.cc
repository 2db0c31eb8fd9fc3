// Teardown that works from names alone (after kill -9 of everything): the
// processes of a namespace are found by inode match of /proc/<pid>/ns/net.
#include <dirent.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>

#include "nns/nns_internal.h"

namespace sitlnet::nns {
namespace {

// Bounded waits for processes to exit after SIGTERM, then after SIGKILL.
constexpr TimeNs kTermWaitNs = 2 * kNsPerS;
constexpr TimeNs kKillWaitNs = 2 * kNsPerS;
// A process may fork while we kill; rescan at most this many times.
constexpr int kMaxKillRounds = 4;

std::string ReadComm(pid_t pid) {
  std::ifstream file("/proc/" + std::to_string(pid) + "/comm");
  std::string comm;
  std::getline(file, comm);
  return comm;
}

// Waits until every pidfd is readable (process exited) or `timeout_ns`
// passes; returns the indices still running. poll() on pidfds is an event
// wait: no sleep, no pid reuse race.
std::vector<size_t> WaitForExit(const std::vector<UniqueFd>& pidfds, std::vector<size_t> pending,
                                TimeNs timeout_ns) {
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  while (!pending.empty()) {
    const TimeNs left_ns = deadline - MonotonicNowNs();
    if (left_ns <= 0) break;
    std::vector<pollfd> fds;
    for (size_t i : pending) fds.push_back(pollfd{pidfds[i].get(), POLLIN, 0});
    const int ready = poll(fds.data(), fds.size(), static_cast<int>(left_ns / kNsPerMs) + 1);
    if (ready < 0 && errno != EINTR) break;
    std::vector<size_t> still;
    for (size_t k = 0; k < fds.size(); ++k) {
      if ((fds[k].revents & (POLLIN | POLLHUP | POLLERR)) == 0) still.push_back(pending[k]);
    }
    pending.swap(still);
  }
  return pending;
}

}  // namespace

namespace internal {

std::vector<ProcessInfo> ScanProcesses(const std::vector<NsId>& namespaces,
                                       std::vector<int>* owner) {
  std::vector<ProcessInfo> found;
  if (owner) owner->clear();
  if (namespaces.empty()) return found;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) throw Error(SystemErrorMessage("list /proc", errno));
  const pid_t self = getpid();
  while (dirent* entry = readdir(proc)) {
    char* end = nullptr;
    const long pid = std::strtol(entry->d_name, &end, 10);
    if (*end != '\0' || pid <= 0 || pid == self) continue;
    NsId id;
    // The thread-group leader's namespace only: a daemon (tapbridge) whose
    // worker thread briefly enters a robot's namespace is not inside it.
    if (!StatNs("/proc/" + std::string(entry->d_name) + "/ns/net", &id)) continue;
    for (size_t i = 0; i < namespaces.size(); ++i) {
      if (namespaces[i] == id) {
        found.push_back(ProcessInfo{static_cast<pid_t>(pid), ReadComm(pid)});
        if (owner) owner->push_back(static_cast<int>(i));
        break;
      }
    }
  }
  closedir(proc);
  return found;
}

void TerminateProcesses(const std::vector<ProcessInfo>& processes, DownReport* report) {
  std::vector<UniqueFd> pidfds;
  std::vector<size_t> pending;
  for (const ProcessInfo& process : processes) {
    UniqueFd fd(static_cast<int>(syscall(SYS_pidfd_open, process.pid, 0)));
    if (!fd.valid()) continue;  // Already gone.
    if (syscall(SYS_pidfd_send_signal, fd.get(), SIGTERM, nullptr, 0) != 0) continue;
    pending.push_back(pidfds.size());
    pidfds.push_back(std::move(fd));
  }
  const size_t signalled = pending.size();
  pending = WaitForExit(pidfds, std::move(pending), kTermWaitNs);
  report->processes_terminated += static_cast<int>(signalled - pending.size());
  if (pending.empty()) return;
  for (size_t i : pending) syscall(SYS_pidfd_send_signal, pidfds[i].get(), SIGKILL, nullptr, 0);
  report->processes_killed += static_cast<int>(pending.size());
  pending = WaitForExit(pidfds, std::move(pending), kKillWaitNs);
  if (!pending.empty()) {
    throw Error("process " + std::to_string(processes[pending[0]].pid) +
                " did not exit within 2 s of SIGKILL (uninterruptible sleep?)");
  }
}

}  // namespace internal

std::vector<ProcessInfo> ProcessesInNetns(const std::string& netns) {
  internal::NsId id;
  if (!internal::StatNs(NetnsPath(netns), &id)) return {};
  return internal::ScanProcesses({id}, nullptr);
}

DownReport Down(const std::string& name) {
  internal::StateLock lock;
  return internal::DownLocked(name);
}

DownReport internal::DownLocked(const std::string& name) {
  DownReport report;
  const std::optional<ScenarioState> state = ReadScenarioState(name);
  if (!state) return report;

  // 0. The scenario's daemons in the root namespace (medium, physics): they
  // hold the TAPs and sockets of the scenario.
  if (const auto daemons = RegisteredDaemons(name); !daemons.empty()) {
    internal::TerminateProcesses(daemons, &report);
  }
  // 1. The scenario's containers, by name with their engine: podman and its conmon are in the
  // root namespace, only the containers' processes in the robots'.
  internal::RemoveRegisteredContainers(name, &report);
  // 1b. The robots' cgroups: every process a robot started, wherever it moved since.
  report.cgroups_removed += internal::RemoveScenarioCgroups(name);
  // 2. Processes, all namespaces of the scenario in one /proc scan per round.
  std::vector<internal::NsId> namespaces;
  if (internal::NsId id; internal::StatNs(NetnsPath(CtlNetnsName(name)), &id)) {
    namespaces.push_back(id);  // Nothing runs there but what someone started by hand.
  }
  for (const OwnedRobot& robot : state->robots) {
    internal::NsId id;
    if (internal::StatNs(NetnsPath(robot.netns), &id)) namespaces.push_back(id);
  }
  for (int round = 0; round < kMaxKillRounds; ++round) {
    const std::vector<ProcessInfo> processes = internal::ScanProcesses(namespaces, nullptr);
    if (processes.empty()) break;
    internal::TerminateProcesses(processes, &report);
  }
  // 3. The ctl namespace: the robots' root-side veths (their ctl0 peers go with them) and the
  // filter go with it. Counted first: the links of ours that are still there.
  const std::string ctl = CtlNetnsName(name);
  if (NetnsExists(ctl)) {
    try {
      ScopedNetns in_ctl(ctl);
      internal::RouteSocket ctl_socket;
      for (const OwnedRobot& robot : state->robots) {
        if (internal::LinkIndex(ctl_socket, robot.root_veth) != 0) ++report.links_removed;
      }
    } catch (const Error&) {
      // Not a namespace (an `up` killed between making the file and mounting it there): nothing
      // to count, and it goes all the same.
    }
    if (RemoveNetns(ctl)) ++report.namespaces_removed;
  }
  // 4. The robots' namespaces (their TAPs and loopback go with the last reference).
  for (const OwnedRobot& robot : state->robots) {
    if (RemoveNetns(robot.netns)) ++report.namespaces_removed;
  }
  internal::RemoveState(name);
  return report;
}

DownReport DownAll() {
  internal::StateLock lock;
  DownReport total;
  for (const std::string& name : ListScenarios()) {
    const DownReport one = internal::DownLocked(name);
    total.namespaces_removed += one.namespaces_removed;
    total.links_removed += one.links_removed;
    total.processes_terminated += one.processes_terminated;
    total.processes_killed += one.processes_killed;
    total.containers_removed += one.containers_removed;
    total.cgroups_removed += one.cgroups_removed;
  }
  return total;
}

}  // namespace sitlnet::nns

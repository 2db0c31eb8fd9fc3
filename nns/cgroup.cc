// Robot cgroups (docs/security.md, "Resource limits"): <mount>/sitlnet/<scenario>/<robot>, one
// per robot whose image is a host program, joined by the robot's process before it runs the
// image, so that every process the robot ever starts is accounted, limited and killed together.
// cgroup v2 holds the membership, the CPU time and the kill (cgroup.kill); a controller that v2
// does not offer here (a hybrid host mounts memory, pids and cpu as v1 hierarchies) is used in its
// v1 hierarchy, in a folder of the same name.
#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "nns/nns_internal.h"
#include "nns/nns.h"

namespace sitlnet::nns {

// Where the cgroup file systems are mounted: /proc/self/mountinfo's "<mount point> ... - <type>
// <source> <super options>" lines.
struct CgroupMounts {
  std::string v2;                         // cgroup2's mount point, "" if none.
  std::map<std::string, std::string> v1;  // controller -> its v1 hierarchy's mount point.
};

namespace {

constexpr const char* kTopFolder = "sitlnet";
// The controllers a robot's cgroup may use beyond v2's own CPU time: memory (peak, limit),
// pids (limit), cpu (limit).
constexpr const char* kControllers[] = {"memory", "pids", "cpu"};
constexpr int64_t kCpuPeriodUs = 100000;
// How long the processes of a killed cgroup may take to be gone.
constexpr TimeNs kKillWaitNs = 5 * kNsPerS;

CgroupMounts FindMounts() {
  CgroupMounts mounts;
  std::ifstream info("/proc/self/mountinfo");
  for (std::string line; std::getline(info, line);) {
    std::istringstream head(line);
    std::string id, parent, device, root, point;
    head >> id >> parent >> device >> root >> point;
    const size_t dash = line.find(" - ");
    if (dash == std::string::npos) continue;
    std::istringstream tail(line.substr(dash + 3));
    std::string type, source, options;
    tail >> type >> source >> options;
    if (type == "cgroup2" && mounts.v2.empty()) mounts.v2 = point;
    if (type != "cgroup") continue;
    std::istringstream list(options);
    for (std::string option; std::getline(list, option, ',');) {
      for (const char* controller : kControllers) {
        if (option == controller) mounts.v1.emplace(option, point);
      }
    }
  }
  return mounts;
}

// Writes `text` to an existing cgroup file; errno on failure, else 0.
int WriteCgroupFile(const std::string& path, const std::string& text) {
  const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  const ssize_t written = write(fd, text.data(), text.size());
  const int err = written == static_cast<ssize_t>(text.size()) ? 0 : (written < 0 ? errno : EIO);
  close(fd);
  return err;
}

std::string ReadCgroupFile(const std::string& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The value after "key " in a flat-keyed file (cpu.stat, cgroup.events), or -1.
int64_t KeyedValue(const std::string& text, const std::string& key) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(key + " ", 0) == 0) return std::stoll(line.substr(key.size() + 1));
  }
  return -1;
}

// Whether the space-separated `list` (cgroup.controllers, cgroup.subtree_control) names `word`.
bool ListHas(const std::string& list, const std::string& word) {
  std::istringstream words(list);
  for (std::string listed; words >> listed;) {
    if (listed == word) return true;
  }
  return false;
}

// mkdir that accepts an existing folder; errno on failure, else 0.
int MakeFolder(const std::string& path) {
  if (mkdir(path.c_str(), 0755) == 0 || errno == EEXIST) return 0;
  return errno;
}

std::vector<std::string> SubFolders(const std::string& dir) {
  std::vector<std::string> names;
  DIR* listing = opendir(dir.c_str());
  if (listing == nullptr) return names;
  while (const dirent* entry = readdir(listing)) {
    const std::string name = entry->d_name;
    if (entry->d_type == DT_DIR && name != "." && name != "..") names.push_back(name);
  }
  closedir(listing);
  return names;
}

// Kills every process of the v2 cgroup `dir` and waits until it is empty (cgroup.events says
// "populated 0", an event poll() reports as POLLPRI), up to `timeout_ns`; true when empty.
bool KillV2Cgroup(const std::string& dir, TimeNs timeout_ns) {
  const std::string events_path = dir + "/cgroup.events";
  const int events = open(events_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (events < 0) return errno == ENOENT;  // Gone already.
  if (WriteCgroupFile(dir + "/cgroup.kill", "1") != 0) {
    // Before Linux 5.14 there is no cgroup.kill: SIGKILL to each process listed, until none is.
    std::istringstream pids(ReadCgroupFile(dir + "/cgroup.procs"));
    for (pid_t pid = 0; pids >> pid;) kill(pid, SIGKILL);
  }
  const TimeNs deadline_ns = MonotonicNowNs() + timeout_ns;
  bool empty = false;
  for (;;) {
    char text[256] = {};
    const ssize_t got = pread(events, text, sizeof text - 1, 0);
    empty = got > 0 && KeyedValue(text, "populated") == 0;
    const TimeNs left_ns = deadline_ns - MonotonicNowNs();
    if (empty || got <= 0 || left_ns <= 0) break;
    pollfd changed{events, POLLPRI, 0};
    poll(&changed, 1, static_cast<int>(left_ns / kNsPerMs) + 1);
    std::istringstream pids(ReadCgroupFile(dir + "/cgroup.procs"));
    for (pid_t pid = 0; pids >> pid;) kill(pid, SIGKILL);  // Any that joined since.
  }
  close(events);
  return empty;
}

// rmdir that counts a folder that is not there as removed.
bool RemoveFolder(const std::string& path) { return rmdir(path.c_str()) == 0 || errno == ENOENT; }

// Removes the scenario's folder of a hierarchy mounted at `mount` if no robot of it uses it any
// more. sitlnet's own folder above stays: another scenario's run may be making its folder in it
// at this moment, and would find it gone.
void RemoveParents(const std::string& mount, const std::string& scenario) {
  RemoveFolder(mount + "/" + kTopFolder + "/" + scenario);
}

}  // namespace

RobotCgroup::RobotCgroup(const std::string& scenario, const std::string& robot,
                         const CgroupLimits& limits)
    : scenario_(scenario), robot_(robot) {
  const std::string who = "robot \"" + robot + "\": ";
  if (robot.empty() || robot.find('/') != std::string::npos || robot[0] == '.') {
    throw Error(who + "not a cgroup name");
  }
  const CgroupMounts mounts = FindMounts();
  const bool wants_limits =
      limits.memory_max_bytes > 0 || limits.pids_max > 0 || limits.cpu_max_cores > 0;
  const auto unavailable = [&](const std::string& why) {
    unavailable_ = why;
    if (wants_limits) throw Error(who + "its image's limits need a cgroup, and " + why);
  };
  if (mounts.v2.empty()) {
    unavailable("this host mounts no cgroup2 file system");
    return;
  }
  // The v2 folders: sitlnet's, the scenario's, the robot's.
  v2_mount_ = mounts.v2;
  const std::string top = mounts.v2 + "/" + kTopFolder;
  const std::string scenario_dir = top + "/" + scenario;
  for (const std::string& dir : {top, scenario_dir}) {
    if (const int err = MakeFolder(dir); err != 0) {
      unavailable(SystemErrorMessage("make cgroup " + dir, err));
      return;
    }
  }
  v2_dir_ = scenario_dir + "/" + robot;
  KillV2Cgroup(v2_dir_, kKillWaitNs);  // A leftover of a run that was killed.
  RemoveFolder(v2_dir_);
  if (const int err = MakeFolder(v2_dir_); err != 0) {
    v2_dir_.clear();
    RemoveParents(v2_mount_, scenario_);
    unavailable(SystemErrorMessage("make cgroup " + scenario_dir + "/" + robot, err));
    return;
  }
  try {
    SetUp(mounts, limits);
  } catch (const Error&) {
    Remove();  // Nothing of the robot runs yet: its folders go.
    throw;
  }
}

void RobotCgroup::SetUp(const CgroupMounts& mounts, const CgroupLimits& limits) {
  const std::string top = mounts.v2 + "/" + kTopFolder;
  const std::string scenario_dir = top + "/" + scenario_;
  // The controllers to use: memory always (its peak is accounted), pids and cpu for a limit.
  std::vector<std::string> wanted = {"memory"};
  if (limits.pids_max > 0) wanted.push_back("pids");
  if (limits.cpu_max_cores > 0) wanted.push_back("cpu");
  const std::string offered = ReadCgroupFile(mounts.v2 + "/cgroup.controllers");
  for (const std::string& controller : wanted) {
    bool in_v2 = ListHas(offered, controller);
    // Enabled for the children of the root (usually done by the host's init), of sitlnet's and of
    // the scenario's folder, none of which holds a process.
    for (const std::string& dir : {mounts.v2, top, scenario_dir}) {
      if (!in_v2) break;
      if (ListHas(ReadCgroupFile(dir + "/cgroup.subtree_control"), controller)) continue;
      in_v2 = WriteCgroupFile(dir + "/cgroup.subtree_control", "+" + controller) == 0;
    }
    if (in_v2) {
      v2_controllers_.push_back(controller);
      continue;
    }
    const auto v1 = mounts.v1.find(controller);
    if (v1 == mounts.v1.end()) continue;
    const std::string v1_top = v1->second + "/" + kTopFolder;
    const std::string dir = v1_top + "/" + scenario_ + "/" + robot_;
    if (MakeFolder(v1_top) != 0 || MakeFolder(v1_top + "/" + scenario_) != 0) continue;
    RemoveFolder(dir);  // A leftover of a run that was killed (empty once v2's was killed).
    if (MakeFolder(dir) == 0) v1_[controller] = V1Folder{v1->second, dir};
  }
  ApplyLimits(limits);
  for (const std::string& dir : Folders()) {
    const std::string procs = dir + "/cgroup.procs";
    UniqueFd fd(open(procs.c_str(), O_WRONLY | O_CLOEXEC));
    if (!fd.valid()) {
      throw Error(SystemErrorMessage("robot \"" + robot_ + "\": open " + procs, errno));
    }
    join_fds_.push_back(std::move(fd));
  }
}

RobotCgroup::~RobotCgroup() {
  KillAll();
  Remove();
}

void RobotCgroup::Remove() {
  join_fds_.clear();
  for (const auto& [controller, folder] : v1_) {
    rmdir(folder.dir.c_str());
    RemoveParents(folder.mount, scenario_);
  }
  if (!v2_dir_.empty()) {
    rmdir(v2_dir_.c_str());
    RemoveParents(v2_mount_, scenario_);
  }
}

std::vector<std::string> RobotCgroup::Folders() const {
  std::vector<std::string> dirs;
  if (!v2_dir_.empty()) dirs.push_back(v2_dir_);
  for (const auto& [controller, folder] : v1_) dirs.push_back(folder.dir);
  return dirs;
}

std::string RobotCgroup::ControllerFolder(const std::string& controller, bool* v2) const {
  for (const std::string& name : v2_controllers_) {
    if (name == controller) {
      *v2 = true;
      return v2_dir_;
    }
  }
  *v2 = false;
  const auto v1 = v1_.find(controller);
  return v1 == v1_.end() ? "" : v1->second.dir;
}

void RobotCgroup::ApplyLimits(const CgroupLimits& limits) {
  const std::string who = "robot \"" + robot_ + "\": ";
  // (controller, the limit's name in the manifest, {v2 file, value}, {v1 files, values}).
  struct Setting {
    const char* controller;
    const char* field;
    std::vector<std::pair<std::string, std::string>> v2;
    std::vector<std::pair<std::string, std::string>> v1;
  };
  std::vector<Setting> settings;
  if (limits.memory_max_bytes > 0) {
    const std::string bytes = std::to_string(limits.memory_max_bytes);
    settings.push_back({"memory",
                        "limits.memory_max_mib",
                        {{"memory.max", bytes}},
                        {{"memory.limit_in_bytes", bytes}}});
  }
  if (limits.pids_max > 0) {
    const std::string count = std::to_string(limits.pids_max);
    settings.push_back({"pids", "limits.pids_max", {{"pids.max", count}}, {{"pids.max", count}}});
  }
  if (limits.cpu_max_cores > 0) {
    const std::string quota =
        std::to_string(std::max<int64_t>(1000, std::llround(limits.cpu_max_cores * kCpuPeriodUs)));
    const std::string period = std::to_string(kCpuPeriodUs);
    settings.push_back({"cpu",
                        "limits.cpu_max_cores",
                        {{"cpu.max", quota + " " + period}},
                        {{"cpu.cfs_period_us", period}, {"cpu.cfs_quota_us", quota}}});
  }
  for (const Setting& setting : settings) {
    bool v2 = false;
    const std::string dir = ControllerFolder(setting.controller, &v2);
    if (dir.empty()) {
      throw Error(who + setting.field + " needs cgroup's " + setting.controller +
                  " controller, which this host does not offer to sitlnet (cgroup v2 or v1)");
    }
    for (const auto& [file, value] : v2 ? setting.v2 : setting.v1) {
      if (const int err = WriteCgroupFile(dir + "/" + file, value); err != 0) {
        throw Error(SystemErrorMessage(
            who + setting.field + ": write " + value + " to " + dir + "/" + file, err));
      }
    }
  }
  // No swap beyond the memory limit where the host has swap: the limit is on what the robot uses.
  if (limits.memory_max_bytes > 0) {
    bool v2 = false;
    const std::string dir = ControllerFolder("memory", &v2);
    if (v2) {
      WriteCgroupFile(dir + "/memory.swap.max", "0");
    } else {
      WriteCgroupFile(dir + "/memory.memsw.limit_in_bytes",
                      std::to_string(limits.memory_max_bytes));
    }
  }
}

std::vector<int> RobotCgroup::join_fds() const {
  std::vector<int> fds;
  for (const UniqueFd& fd : join_fds_) fds.push_back(fd.get());
  return fds;
}

CgroupUsage RobotCgroup::Usage() const {
  CgroupUsage usage;
  if (v2_dir_.empty()) return usage;
  const int64_t cpu_us = KeyedValue(ReadCgroupFile(v2_dir_ + "/cpu.stat"), "usage_usec");
  if (cpu_us >= 0) usage.cpu_ns = cpu_us * 1000;
  bool v2 = false;
  const std::string memory = ControllerFolder("memory", &v2);
  if (!memory.empty()) {
    const std::string peak =
        ReadCgroupFile(memory + (v2 ? "/memory.peak" : "/memory.max_usage_in_bytes"));
    if (!peak.empty() && std::isdigit(static_cast<unsigned char>(peak[0]))) {
      usage.memory_peak_bytes = std::stoll(peak);
    }
  }
  return usage;
}

bool RobotCgroup::KillAll() { return v2_dir_.empty() || KillV2Cgroup(v2_dir_, kKillWaitNs); }

namespace internal {

int RemoveScenarioCgroups(const std::string& scenario) {
  const CgroupMounts mounts = FindMounts();
  int removed = 0;
  if (!mounts.v2.empty()) {
    const std::string dir = mounts.v2 + "/" + kTopFolder + "/" + scenario;
    for (const std::string& robot : SubFolders(dir)) {
      KillV2Cgroup(dir + "/" + robot, kKillWaitNs);
      if (RemoveFolder(dir + "/" + robot)) ++removed;
    }
    RemoveParents(mounts.v2, scenario);
  }
  for (const auto& [controller, mount] : mounts.v1) {
    const std::string dir = mount + "/" + kTopFolder + "/" + scenario;
    for (const std::string& robot : SubFolders(dir)) RemoveFolder(dir + "/" + robot);
    RemoveParents(mount, scenario);
  }
  return removed;
}

}  // namespace internal
}  // namespace sitlnet::nns

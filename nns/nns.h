// sitlnet nns: robot network namespaces, their TAP and veth devices,
// addresses, isolation and teardown, with libnl (no shelling out to `ip`).
// Design, ownership rule and measured costs: docs/nns.md.
#ifndef SITLNET_NNS_NNS_H_
#define SITLNET_NNS_NNS_H_

#include <sys/types.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/common.h"
#include "scenario/scenario.h"

namespace sitlnet::nns {

//-------------------------------- Privileges --------------------------------

// One line naming what the calling process lacks (CAP_NET_ADMIN,
// CAP_SYS_ADMIN, read-write /dev/net/tun) and how to get it (sudo, or the
// docker flags); nullopt when everything needed is there.
std::optional<std::string> MissingPrivileges();

// Throws PrivilegeError with MissingPrivileges()'s line, if any.
class PrivilegeError : public Error {
 public:
  using Error::Error;
};
void RequirePrivileges();

//----------------------------- Named namespaces -----------------------------

// Directory of named network namespaces, shared with iproute2 (`ip netns`).
inline constexpr const char* kNetnsDir = "/run/netns";

// "/run/netns/<name>".
std::string NetnsPath(const std::string& name);

// True if /run/netns/<name> exists (whether or not something is mounted on it).
bool NetnsExists(const std::string& name);

// Creates a named namespace exactly as `ip netns add` does: /run/netns as a
// shared mount, an empty file, a new namespace bind-mounted onto it. Throws
// Error if the name exists. Does not change the calling thread's namespace.
void CreateNetns(const std::string& name);

// Unmounts and removes /run/netns/<name> (lazy unmount, as `ip netns del`).
// Returns false if it did not exist. Processes inside are NOT killed: see Down.
bool RemoveNetns(const std::string& name);

// Opens the namespace file (O_RDONLY|O_CLOEXEC), for setns or IFLA_NET_NS_FD.
UniqueFd OpenNetns(const std::string& name);

// A wrapper that runs its argument with the calling thread in namespace `name` (ScopedNetns), for
// a library that makes its sockets through one (physics::ServerOptions::make_sockets).
std::function<void(const std::function<void()>&)> InNetns(const std::string& name);

// The namespace of a scenario's ctl links, "<scenario>.ctl" (a robot's is "<scenario>-<robot>";
// neither name can hold a '.'). The root side of every robot's ctl0 (the veth "<scenario>-c<i>",
// its address, the filter) and the physics server's sockets live there, not in the host's
// namespace: no local user can bind a robot's physics port before the run (audit finding 10),
// and ctl0 leads to nothing of the host. `up` makes it, `down` removes it.
std::string CtlNetnsName(const std::string& scenario);

// Moves the calling thread into namespace `name` and back on destruction.
// setns affects only the calling thread: use it on the thread that will open
// sockets or TAPs, and do not hand the scope to another thread. A netlink or
// UDP socket opened inside stays bound to that namespace after leaving.
class ScopedNetns {
 public:
  explicit ScopedNetns(const std::string& name);
  explicit ScopedNetns(int netns_fd);  // Does not take ownership of netns_fd.
  ~ScopedNetns();
  ScopedNetns(const ScopedNetns&) = delete;
  ScopedNetns& operator=(const ScopedNetns&) = delete;

 private:
  void Enter(int netns_fd, const std::string& what);
  UniqueFd original_;
};

//----------------------------------- TAP ------------------------------------

// Opens the existing (persistent) TAP `ifname` inside namespace `netns` with
// IFF_TAP|IFF_NO_PI and returns its fd, usable from any thread and namespace.
// `nonblocking` sets O_NONBLOCK (the tapbridge drains to EAGAIN). Throws Error
// if the device does not exist or is not a TAP.
UniqueFd AttachTap(const std::string& netns, const std::string& ifname, bool nonblocking = true);

//------------------------------- Host routes --------------------------------

// IPv4 routes of the main table of the calling thread's namespace, read with
// libnl, for CheckAddressPlanAgainstRoutes.
std::vector<HostRoute> ReadHostRoutes();

//------------------------- Scenario state (ownership) -----------------------

// `up` writes /run/sitlnet/<scenario>/state BEFORE it creates anything: a
// namespace or device with one of our names is ours only if the state file of
// that scenario lists it. `down` and `exec` read it; /run is a tmpfs, so it
// vanishes at reboot together with the namespaces.
inline constexpr const char* kStateDir = "/run/sitlnet";

// One robot as the state file records it: what `up` created for it and `down` removes.
struct OwnedRobot {
  int index = 0;
  std::string name;
  std::string netns;
  std::string root_veth;
  Ipv4 wlan_address;
  Ipv4 ctl_root_address;
  Ipv4 ctl_robot_address;
};

struct ScenarioState {
  std::string name;
  std::string source_path;
  int physics_port = 0;
  std::vector<OwnedRobot> robots;

  // "<ctl_root_address>:<physics_port>" of robot `index` (SITLNET_PHYSICS_ADDR).
  std::string PhysicsAddress(const OwnedRobot& robot) const;
};

// The state of the robots of `robots` (Scenario::RobotSlice: empty means all).
ScenarioState StateFromScenario(const Scenario& scenario, const std::vector<int>& robots = {});
std::string FormatState(const ScenarioState& state);
// Throws Error naming `source` and the line on malformed text.
ScenarioState ParseState(const std::string& text, const std::string& source);

// Scenarios that have a state file, sorted by name.
std::vector<std::string> ListScenarios();
// The state of scenario `name`, or nullopt if it has none.
std::optional<ScenarioState> ReadScenarioState(const std::string& name);

// A robot picked by the user: "robot" (unique among the scenarios up),
// "<scenario>-<robot>" (its namespace name), or `scenario` + "robot".
struct RobotRef {
  ScenarioState scenario;
  OwnedRobot robot;
};
// Throws Error (one line, listing candidates when ambiguous) if not found.
RobotRef ResolveRobot(const std::vector<ScenarioState>& scenarios, const std::string& robot,
                      const std::string& scenario_name = "");

//------------------------------ Scenario daemons -----------------------------

// A root-namespace daemon of a scenario (role "medium", "physics" or "run") records
// "<pid> <start time>" in /run/sitlnet/<scenario>/<role>.pid for as long as
// this object lives, so that Down() stops it too (also after the daemon's
// parent crashed). Throws Error if the scenario is not up.
class DaemonRegistration {
 public:
  DaemonRegistration(const std::string& scenario, const std::string& role);
  ~DaemonRegistration();
  DaemonRegistration(const DaemonRegistration&) = delete;
  DaemonRegistration& operator=(const DaemonRegistration&) = delete;

 private:
  std::string path_;
};

// A container of the scenario (an OCI robot image, docs/containers.md) recorded as
// /run/sitlnet/<scenario>/container.<name> (holding the engine's path) for as long as this
// object lives, so that Down() removes it by its exact name with that engine, also after the
// process that started it was killed. Throws Error if the scenario is not up, or for an engine
// other than podman or a name that is not a container name of sitlnet's ("sitlnet-...").
class ContainerRegistration {
 public:
  ContainerRegistration(const std::string& scenario, const std::string& engine_exe,
                        const std::string& name);
  ~ContainerRegistration();
  ContainerRegistration(const ContainerRegistration&) = delete;
  ContainerRegistration& operator=(const ContainerRegistration&) = delete;

 private:
  std::string path_;
};

//-------------------------------- Cgroups -----------------------------------

// Limits of a robot's cgroup (an image manifest's `limits`); 0: none.
struct CgroupLimits {
  int64_t memory_max_bytes = 0;  // RAM (and no swap beyond it).
  int64_t pids_max = 0;          // Processes and threads.
  double cpu_max_cores = 0;      // CPU time per wall second, in cores.
};

// What a robot's cgroup measured of all its processes, past and present.
struct CgroupUsage {
  TimeNs cpu_ns = -1;              // User and system CPU time; -1: not accounted.
  int64_t memory_peak_bytes = -1;  // Peak memory (with the page cache it caused); -1: not here.
};

struct CgroupMounts;  // Where the cgroup file systems are mounted (cgroup.cc).

// A robot's cgroup, <mount>/sitlnet/<scenario>/<robot>, for as long as this object lives
// (docs/security.md, "Resource limits"). cgroup v2 holds the membership, the CPU time and the
// kill; memory (always, for its peak), pids and cpu (for a limit) are used in v2 if the host
// offers them there, else in their v1 hierarchies. The robot's process joins it before it runs
// the image by writing "0" to each of join_fds() (async-signal-safe, between fork and exec), so
// its whole process tree is in it. Without cgroup2 or with a read-only cgroup file system (in
// some containers) it is unavailable: unavailable() says why, and nothing is accounted. Throws
// Error naming the robot and the field when a limit cannot be applied (also when unavailable).
// The destructor kills what is left in it and removes its folders.
class RobotCgroup {
 public:
  RobotCgroup(const std::string& scenario, const std::string& robot,
              const CgroupLimits& limits = {});
  ~RobotCgroup();
  RobotCgroup(const RobotCgroup&) = delete;
  RobotCgroup& operator=(const RobotCgroup&) = delete;

  // Why there is no cgroup ("" when there is one).
  const std::string& unavailable() const { return unavailable_; }
  // cgroup.procs of each folder, open for writing, close-on-exec; empty when unavailable.
  std::vector<int> join_fds() const;
  CgroupUsage Usage() const;
  // SIGKILL to every process in it (cgroup.kill), and waits until none is left (up to 5 s);
  // false if some still are. Robots that double-fork, change session or namespace are in it.
  bool KillAll();

 private:
  struct V1Folder {
    std::string mount;
    std::string dir;
  };
  // Everything after the v2 folder: controllers, v1 folders, limits, join_fds_.
  void SetUp(const CgroupMounts& mounts, const CgroupLimits& limits);
  void Remove();  // The robot's folders, then the scenario's and sitlnet's if empty.
  std::vector<std::string> Folders() const;
  // The folder whose files control `controller` (and whether it is v2's), "" if none.
  std::string ControllerFolder(const std::string& controller, bool* v2) const;
  void ApplyLimits(const CgroupLimits& limits);

  std::string scenario_;
  std::string robot_;
  std::string unavailable_;
  std::string v2_mount_;
  std::string v2_dir_;
  std::vector<std::string> v2_controllers_;
  std::map<std::string, V1Folder> v1_;  // Controller -> its v1 folder.
  std::vector<UniqueFd> join_fds_;
};

//-------------------------------- Up / down ---------------------------------

struct UpOptions {
  // Called after robot `robots_done` (1-based count) is fully configured.
  // Throwing from it aborts `up`, which then rolls back (used by tests and by
  // the CLI's fault-injection hook, docs/nns.md).
  std::function<void(int robots_done)> on_robot_done;
  // The calling process holds the scenario for as long as it runs (`sitlnet run`): recorded,
  // under the state lock, as the scenario's "run" daemon, so that another `up` or `run` of it
  // is refused instead of tearing it down, and `down` stops it.
  bool register_caller_as_run = false;
  // The robots to bring up, by global index, ascending (Scenario::RobotSlice); empty: all. A
  // node host (issue 35) brings up its own robots only, under their usual names; the state file
  // lists only them, so `down` removes exactly them.
  std::vector<int> robots = {};
};

// Brings the scenario's robots (options.robots) up (see docs/nns.md for the exact devices):
// privileges, `down` of our own leftovers, refusal of foreign objects with our
// names and of address clashes with host routes (nothing touched), then per
// robot: namespace, lo, wlan0 TAP, ctl0 veth, addresses, isolation. Any
// failure rolls back everything created and rethrows.
void Up(const Scenario& scenario, const UpOptions& options = {});

struct DownReport {
  int namespaces_removed = 0;
  int links_removed = 0;
  int processes_terminated = 0;  // Exited after SIGTERM.
  int processes_killed = 0;      // Needed SIGKILL.
  int containers_removed = 0;    // Registered containers (ContainerRegistration) removed.
  int cgroups_removed = 0;       // Robots' cgroups (RobotCgroup) killed and removed.
};

// Tears scenario `name` down from its state file: SIGTERM then SIGKILL its
// registered daemons (DaemonRegistration) and every process in its namespaces (bounded wait on
// pidfds), remove its registered containers (ContainerRegistration) and its robots' cgroups
// (RobotCgroup: what is in them killed), unmount and remove the
// namespaces, delete the root-side veths by exact name, remove the state. Idempotent; a scenario
// without a state file is a no-op.
DownReport Down(const std::string& name);
// Down for every scenario in ListScenarios().
DownReport DownAll();

//--------------------------------- Status -----------------------------------

struct ProcessInfo {
  pid_t pid = 0;
  std::string command;  // /proc/<pid>/comm
};

struct LinkInfo {
  std::string name;
  std::string kind;  // "tun", "veth", "loopback", ...
  bool up = false;
  std::string mac;
  std::vector<std::string> ipv4;  // "a.b.c.d/len"
  int txqueuelen = 0;
};

struct RobotStatus {
  OwnedRobot robot;
  bool netns_present = false;
  bool root_veth_present = false;
  std::vector<LinkInfo> links;  // Inside the robot's namespace.
  std::vector<ProcessInfo> processes;
};

// Reads devices and processes of every robot of `state`.
std::vector<RobotStatus> Status(const ScenarioState& state);

// Throws Error naming them if `scenario` has a live run or daemon (`Up` checks it under the
// state lock; callers may check first, before they create anything of their own).
void RefuseIfInUse(const std::string& scenario);

// Live daemons registered for `scenario` (pid and start time still match), the calling
// process excluded.
std::vector<ProcessInfo> RegisteredDaemons(const std::string& scenario);

// Processes whose network namespace is /run/netns/<netns> (inode match on
// /proc/<pid>/ns/net). Empty if the namespace does not exist.
std::vector<ProcessInfo> ProcessesInNetns(const std::string& netns);

}  // namespace sitlnet::nns

#endif  // SITLNET_NNS_NNS_H_

// `up`: checks that touch nothing, then the state file, then per robot the
// namespace and its devices; any failure rolls back through Down().
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "nns/nns_internal.h"

namespace sitlnet::nns {
namespace {

using internal::RouteSocket;

// ctl0 is a point-to-point /30 per robot: .1 root side, .2 robot side.
constexpr int kCtlPrefixLength = 30;

// Robots are created by this many threads: namespace creation is mostly
// kernel time, and two threads use both cores of the target machine
// (measured in docs/performance.md).
constexpr int kUpThreads = 2;

void RefuseForeignObjects(const Scenario& scenario, const std::vector<int>& robots) {
  const std::string hint = "; nothing was changed";
  for (const int index : robots) {
    const RobotPlan& robot = scenario.robots[index];
    if (NetnsExists(robot.netns)) {
      throw Error("namespace \"" + robot.netns + "\" of robot \"" + robot.name +
                  "\" exists but scenario \"" + scenario.name +
                  "\" did not create it (no state in " + kStateDir + "/" + scenario.name +
                  "): remove it (ip netns del " + robot.netns + ") or rename the scenario" + hint);
    }
  }
  // The robots' root-side veths and the filter live in it: a namespace of that name that is not
  // ours could hold anything.
  const std::string ctl = CtlNetnsName(scenario.name);
  if (NetnsExists(ctl)) {
    throw Error(
        "namespace \"" + ctl + "\" of scenario \"" + scenario.name +
        "\"'s ctl links exists but the scenario did not create it: remove it (ip netns del " + ctl +
        ") or rename the scenario" + hint);
  }
}

// One robot, see docs/nns.md. `ctl_side` is a socket of the scenario's ctl namespace, which the
// calling thread is in.
void UpRobot(const Scenario& scenario, const RobotPlan& robot, const RouteSocket& ctl_side) {
  const auto& plan = scenario.spec.addresses();
  const bool silent = plan.ipv6() == proto::AddressPlan::IPV6_SILENT;
  const std::string who = "robot \"" + robot.name + "\" (namespace \"" + robot.netns + "\")";

  UniqueFd robot_netns;
  std::unique_ptr<RouteSocket> inside;
  {
    UniqueFd self(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC));
    if (!self.valid()) throw Error(SystemErrorMessage("open own network namespace", errno));
    ScopedNetns back_to_ctl(self.get());  // Restores this thread on scope exit.
    internal::CreateNetnsAndEnter(robot.netns);
    robot_netns.Reset(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC));
    if (!robot_netns.valid()) throw Error(SystemErrorMessage(who + ": open namespace", errno));
    inside = std::make_unique<RouteSocket>();  // Stays bound to the robot's namespace.
    // Born inside the namespace (docs/references.md#linux): no move, no name clash.
    internal::CreatePersistentTap("wlan0", who + ": create TAP wlan0");
    // Unmodified ping and robot software without CAP_NET_RAW (docs/security.md). Best effort:
    // without a /proc/sys the kernel default stays, where ping needs CAP_NET_RAW.
    internal::AllowUnprivilegedPing();
  }

  const int lo = internal::LinkIndex(*inside, "lo");
  internal::SetLinkUp(*inside, lo, who + ": lo");

  const int wlan = internal::LinkIndex(*inside, "wlan0");
  if (wlan == 0) throw Error(who + ": TAP wlan0 vanished after creation");
  internal::LinkSettings wlan_settings;
  wlan_settings.mac = &robot.wlan_mac;
  wlan_settings.txqueuelen = static_cast<int>(plan.txqueuelen());
  wlan_settings.ipv6_silent = silent;
  internal::ConfigureLink(*inside, wlan, wlan_settings, who + ": wlan0");
  internal::AddIpv4Address(*inside, wlan, robot.wlan_address, scenario.wlan_subnet.length,
                           who + ": wlan0");
  internal::SetLinkUp(*inside, wlan, who + ": wlan0");
  if (scenario.lockstep()) {
    // Lockstep needs every frame to leave in the step that produced it; an
    // ARP exchange would delay the first send to a peer by the kernel's own
    // timers (docs/references.md#linux, "Lockstep and the TAP"). MACs are known in advance:
    // RobotMac(index).
    for (const RobotPlan& peer : scenario.robots) {
      if (peer.index == robot.index) continue;
      internal::AddPermanentNeighbour(*inside, wlan, peer.wlan_address, peer.wlan_mac,
                                      who + ": wlan0");
    }
  }

  internal::CreateVeth(ctl_side, robot.root_veth, internal::LinkGroupForScenario(scenario.name),
                       "ctl0", robot_netns.get(),
                       who + ": create veth \"" + robot.root_veth + "\" <-> ctl0");
  const int root_side = internal::LinkIndex(ctl_side, robot.root_veth);
  internal::LinkSettings root_settings;
  root_settings.ipv6_silent = silent;
  root_settings.ipv4_no_forwarding = true;
  root_settings.multicast_off = true;
  root_settings.ipv4_own_address_only = true;
  internal::ConfigureLink(ctl_side, root_side, root_settings, who + ": " + robot.root_veth);
  internal::RefuseRouterAdvertisements(robot.root_veth, who + ": " + robot.root_veth);
  internal::AddIpv4Address(ctl_side, root_side, robot.ctl_root_address, kCtlPrefixLength,
                           who + ": " + robot.root_veth);
  internal::SetLinkUp(ctl_side, root_side, who + ": " + robot.root_veth);

  const int ctl = internal::LinkIndex(*inside, "ctl0");
  internal::LinkSettings ctl_settings;
  ctl_settings.ipv6_silent = silent;
  ctl_settings.multicast_off = true;  // Discovery must not bypass the medium.
  internal::ConfigureLink(*inside, ctl, ctl_settings, who + ": ctl0");
  internal::AddIpv4Address(*inside, ctl, robot.ctl_robot_address, kCtlPrefixLength, who + ": ctl0");
  internal::SetLinkUp(*inside, ctl, who + ": ctl0");
  // No default route, ever: the robot reaches its wlan subnet and its /30.
}

// The robots of `robots` (global indices).
void UpAllRobots(const Scenario& scenario, const std::vector<int>& robots,
                 const UpOptions& options) {
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::exception_ptr first_error;
  int robots_done = 0;
  auto worker = [&] {
    try {
      // The root sides are made in the ctl namespace (their sysctls are this thread's).
      ScopedNetns in_ctl(CtlNetnsName(scenario.name));
      RouteSocket ctl;  // One per thread: libnl sockets are not thread-safe.
      for (size_t i = next++; i < robots.size() && !failed; i = next++) {
        UpRobot(scenario, scenario.robots[robots[i]], ctl);
        std::lock_guard<std::mutex> lock(mutex);
        ++robots_done;
        if (options.on_robot_done) options.on_robot_done(robots_done);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!first_error) first_error = std::current_exception();
      failed = true;
    }
  };
  const int threads = std::min<int>(kUpThreads, static_cast<int>(robots.size()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace

void RefuseIfInUse(const std::string& scenario) {
  const std::vector<ProcessInfo> live = RegisteredDaemons(scenario);
  if (live.empty()) return;
  std::string who;
  for (const ProcessInfo& daemon : live) {
    who += (who.empty() ? "" : ", ") + std::string("sitlnet ") + daemon.command + " (pid " +
           std::to_string(daemon.pid) + ")";
  }
  throw Error("scenario \"" + scenario + "\" is running: " + who + "; stop it, or `sitlnet down " +
              scenario + "` ends it");
}

void Up(const Scenario& scenario, const UpOptions& options) {
  const std::vector<int> robots = scenario.RobotSlice(options.robots);  // Bad input: touch nothing.
  RequirePrivileges();
  internal::StateLock lock;
  RefuseIfInUse(scenario.name);         // Never torn down from under its run (audit finding 6).
  internal::DownLocked(scenario.name);  // Our own leftovers (a crash, a previous up).
  RefuseForeignObjects(scenario, robots);
  const std::vector<HostRoute> routes = ReadHostRoutes();
  CheckAddressPlanAgainstRoutes(scenario, routes);
  // Ownership first: from here on, whatever exists under our names is ours.
  internal::WriteState(StateFromScenario(scenario, robots));
  try {
    if (options.register_caller_as_run) internal::WritePidFile(scenario.name, "run");
    {
      // The ctl namespace, its loopback up (the physics server's own traffic), and the filter
      // before the first veth: no moment in which a robot reaches more than its physics ports.
      UniqueFd self(open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC));
      if (!self.valid()) throw Error(SystemErrorMessage("open own network namespace", errno));
      ScopedNetns back(self.get());
      internal::CreateNetnsAndEnter(CtlNetnsName(scenario.name));
      RouteSocket ctl;
      internal::SetLinkUp(ctl, internal::LinkIndex(ctl, "lo"),
                          "scenario \"" + scenario.name + "\": ctl namespace lo");
      internal::AddCtlFilter(scenario, robots);
    }
    UpAllRobots(scenario, robots, options);
  } catch (...) {
    try {
      internal::DownLocked(scenario.name);
    } catch (...) {
      // Keep the original error; `sitlnet down` can finish the job.
    }
    throw;
  }
}

}  // namespace sitlnet::nns

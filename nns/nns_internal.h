// nns internals shared by the library's files; not part of the public API.
#ifndef SITLNET_NNS_NNS_INTERNAL_H_
#define SITLNET_NNS_NNS_INTERNAL_H_

#include <sys/types.h>

#include <string>
#include <string_view>
#include <vector>

#include "nns/nns.h"

struct nl_sock;
struct rtnl_link;

namespace sitlnet::nns::internal {

//--------------------------------- netlink ----------------------------------

// A connected NETLINK_ROUTE socket, bound to the namespace of the thread that
// created it (the kernel keeps it there after the thread leaves).
class RouteSocket {
 public:
  RouteSocket();
  ~RouteSocket();
  RouteSocket(const RouteSocket&) = delete;
  RouteSocket& operator=(const RouteSocket&) = delete;
  nl_sock* get() const { return sock_; }

 private:
  nl_sock* sock_ = nullptr;
};

// Owns a struct rtnl_link*.
struct LinkDeleter {
  void operator()(rtnl_link* link) const;
};

// Interface index of `name` in the socket's namespace, or 0 if absent.
int LinkIndex(const RouteSocket& sock, const std::string& name);

// Settings applied to a link before it goes up (one RTM_NEWLINK change).
struct LinkSettings {
  const MacAddress* mac = nullptr;  // Null: keep.
  int txqueuelen = 0;               // 0: keep.
  bool ipv6_silent = false;         // addrgenmode none (must precede link-up).
  bool multicast_off = false;       // Clear IFF_MULTICAST.
  bool ipv4_no_forwarding = false;  // Per-interface forwarding=0, proxy_arp=0.
  // ARP answers only for this device's own address (arp_ignore=1, arp_announce=2) and strict
  // reverse-path filtering (rp_filter=1): what a robot may discover through its ctl0.
  bool ipv4_own_address_only = false;
};
// Writes `value` to `path`, a network sysctl under /proc/sys/net, for the calling thread's
// namespace; where /proc/sys is mounted read-only (a container) through a child that remounts
// it writable in a mount namespace of its own. 0, or the errno.
int WriteNetSysctl(const std::string& path, std::string_view value);
// Never accept IPv6 router advertisements on device `name` of the calling thread's namespace
// (/proc/sys/net/ipv6/conf/<name>/accept_ra = 0; IPv6 devconf is read-only over netlink).
// A host without IPv6 has nothing to refuse. Throws Error naming `what` if it cannot be set.
void RefuseRouterAdvertisements(const std::string& name, const std::string& what);
// `what` names the device and robot for error messages.
void ConfigureLink(const RouteSocket& sock, int ifindex, const LinkSettings& settings,
                   const std::string& what);
void AddIpv4Address(const RouteSocket& sock, int ifindex, Ipv4 address, int prefix_length,
                    const std::string& what);
void SetLinkUp(const RouteSocket& sock, int ifindex, const std::string& what);

// Creates veth `root_name` in link group `group` of the socket's namespace,
// with peer `peer_name` in the namespace `peer_netns_fd`. Throws Error (EEXIST
// included).
void CreateVeth(const RouteSocket& sock, const std::string& root_name, uint32_t group,
                const std::string& peer_name, int peer_netns_fd, const std::string& what);

// Adds (or replaces) a PERMANENT neighbour entry `address` -> `mac` on
// `ifindex`: sends to that address never wait for ARP.
void AddPermanentNeighbour(const RouteSocket& sock, int ifindex, Ipv4 address,
                           const MacAddress& mac, const std::string& what);

// Every link of the socket's namespace with its IPv4 addresses.
std::vector<LinkInfo> DumpLinks(const RouteSocket& sock);

//----------------------------------- TAP ------------------------------------

// Creates the persistent TAP `ifname` in the CALLING THREAD's namespace.
void CreatePersistentTap(const std::string& ifname, const std::string& what);

//------------------------------ Namespaces ----------------------------------

// Makes /run/netns exist and be a shared mount (once per process).
void PrepareNetnsDir();

// Creates namespace `name` and leaves the CALLING THREAD inside it; the caller
// must restore its namespace (ScopedNetns on the original fd does).
void CreateNetnsAndEnter(const std::string& name);

// Sets net.ipv4.ping_group_range to "0 2147483647" in the CALLING THREAD's namespace (what
// systemd sets on a host): every user may open ICMP datagram sockets (ping(8) falls back to
// them), so ping and robot software need no CAP_NET_RAW there (WriteNetSysctl). Best effort:
// false when /proc/sys is absent or cannot be written.
bool AllowUnprivilegedPing();

// Namespace identity (st_dev, st_ino) of a namespace file.
struct NsId {
  dev_t dev = 0;
  ino_t ino = 0;
  friend bool operator==(const NsId&, const NsId&) = default;
};
bool StatNs(const std::string& path, NsId* id);

//------------------------------- Processes ----------------------------------

// Main threads whose /proc/<pid>/ns/net is one of `namespaces`; `owner[i]` is
// the index in `namespaces` of process i. The scan skips the calling process.
std::vector<ProcessInfo> ScanProcesses(const std::vector<NsId>& namespaces,
                                       std::vector<int>* owner);

// SIGTERM, bounded wait on pidfds, SIGKILL for survivors, bounded wait.
void TerminateProcesses(const std::vector<ProcessInfo>& processes, DownReport* report);

//--------------------------------- State ------------------------------------

std::string StatePath(const std::string& scenario);

// Exclusive lock on /run/sitlnet/.lock for the lifetime of the object: `up`
// and `down` of any scenario run one at a time, so that the checks (names,
// routes) and the creation they guard cannot interleave. flock: released by
// the kernel when the process dies, kill -9 included.
class StateLock {
 public:
  StateLock();

 private:
  UniqueFd fd_;
};

// Down without taking the lock (the caller holds it).
DownReport DownLocked(const std::string& name);
// Link group of the scenario's root-side veths, derived from its name.
uint32_t LinkGroupForScenario(const std::string& scenario);
void WriteState(const ScenarioState& state);  // Atomic (write + rename).
// Throws Error "scenario "x" is not up (no <dir>); run sitlnet up first" without its state
// directory.
void RequireScenarioUp(const std::string& scenario);
// Records the calling process as the scenario's daemon `role` (<role>.pid: pid and start time).
void WritePidFile(const std::string& scenario, const std::string& role);
void RemoveState(const std::string& scenario);
// Removes every container registered for the scenario (ContainerRegistration) with its engine,
// by exact name, and its registration; throws Error naming the first that could not be removed.
void RemoveRegisteredContainers(const std::string& scenario, DownReport* report);
// The scenario's nftables table on the root side of its ctl0 links (ctl_filter.cc), added in the
// CALLING THREAD's namespace (the scenario's ctl namespace; it goes with it): a robot reaches
// only its own ctl0's root address, on the physics server's ports for it, and ping. For the
// robots of `robots` (global indices, the ones `up` creates). Throws Error naming the scenario
// and nft's message.
void AddCtlFilter(const Scenario& scenario, const std::vector<int>& robots);
// Kills what is left in the scenario's robots' cgroups and removes their folders (RobotCgroup);
// the number of robots' v2 cgroups removed.
int RemoveScenarioCgroups(const std::string& scenario);

}  // namespace sitlnet::nns::internal

#endif  // SITLNET_NNS_NNS_INTERNAL_H_

// Links, addresses and routes over NETLINK_ROUTE with libnl-route-3.
#include <arpa/inet.h>
#include <fcntl.h>
#include <linux/if_link.h>
#include <linux/ip.h>
#include <net/if.h>
#include <netlink/netlink.h>
#include <netlink/route/addr.h>
#include <netlink/route/link.h>
#include <netlink/route/link/inet.h>
#include <netlink/route/link/inet6.h>
#include <netlink/route/link/veth.h>
#include <netlink/route/nexthop.h>
#include <netlink/route/route.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>

#include "nns/nns_internal.h"

namespace sitlnet::nns {
namespace internal {
namespace {

std::string NlError(const std::string& what, int err) { return what + ": " + nl_geterror(err); }

struct AddrDeleter {
  void operator()(nl_addr* addr) const { nl_addr_put(addr); }
};
struct RtnlAddrDeleter {
  void operator()(rtnl_addr* addr) const { rtnl_addr_put(addr); }
};
struct CacheDeleter {
  void operator()(nl_cache* cache) const { nl_cache_free(cache); }
};
using LinkPtr = std::unique_ptr<rtnl_link, LinkDeleter>;

LinkPtr LinkWithIndex(int ifindex) {
  LinkPtr link(rtnl_link_alloc());
  SITLNET_DEMAND(link != nullptr);
  rtnl_link_set_ifindex(link.get(), ifindex);
  return link;
}

void Change(const RouteSocket& sock, int ifindex, rtnl_link* changes, const std::string& what) {
  LinkPtr original = LinkWithIndex(ifindex);
  const int err = rtnl_link_change(sock.get(), original.get(), changes, 0);
  if (err < 0) throw Error(NlError(what, err));
}

}  // namespace

void LinkDeleter::operator()(rtnl_link* link) const { rtnl_link_put(link); }

RouteSocket::RouteSocket() {
  sock_ = nl_socket_alloc();
  if (sock_ == nullptr) throw Error("allocate netlink socket: out of memory");
  const int err = nl_connect(sock_, NETLINK_ROUTE);
  if (err < 0) {
    nl_socket_free(sock_);
    throw Error(NlError("connect NETLINK_ROUTE socket", err));
  }
}

RouteSocket::~RouteSocket() { nl_socket_free(sock_); }

int LinkIndex(const RouteSocket& sock, const std::string& name) {
  rtnl_link* raw = nullptr;
  if (rtnl_link_get_kernel(sock.get(), 0, name.c_str(), &raw) < 0) return 0;
  LinkPtr link(raw);
  return rtnl_link_get_ifindex(link.get());
}

void ConfigureLink(const RouteSocket& sock, int ifindex, const LinkSettings& settings,
                   const std::string& what) {
  LinkPtr changes(rtnl_link_alloc());
  SITLNET_DEMAND(changes != nullptr);
  std::unique_ptr<nl_addr, AddrDeleter> mac;
  if (settings.mac != nullptr) {
    mac.reset(nl_addr_build(AF_LLC, settings.mac->bytes.data(), settings.mac->bytes.size()));
    rtnl_link_set_addr(changes.get(), mac.get());
  }
  if (settings.txqueuelen > 0) rtnl_link_set_txqlen(changes.get(), settings.txqueuelen);
  if (settings.multicast_off) rtnl_link_unset_flags(changes.get(), IFF_MULTICAST);
  if (settings.ipv6_silent) {
    // Before link-up: no link-local address, hence no DAD, MLD or RS (docs/references.md#linux).
    const int err = rtnl_link_inet6_set_addr_gen_mode(changes.get(), IN6_ADDR_GEN_MODE_NONE);
    if (err < 0) throw Error(NlError(what + ": addrgenmode none", err));
  }
  if (settings.ipv4_no_forwarding) {
    // Per-interface, applied through IFLA_INET_CONF: packets arriving on this
    // device are never routed on, whatever net.ipv4.ip_forward says.
    rtnl_link_inet_set_conf(changes.get(), IPV4_DEVCONF_FORWARDING, 0);
    rtnl_link_inet_set_conf(changes.get(), IPV4_DEVCONF_PROXY_ARP, 0);
  }
  if (settings.ipv4_own_address_only) {
    // Linux answers ARP for any local address on any interface (weak host model): a robot
    // would learn how to reach every address of the host through its ctl0 (audit finding 3).
    rtnl_link_inet_set_conf(changes.get(), IPV4_DEVCONF_ARP_IGNORE, 1);
    rtnl_link_inet_set_conf(changes.get(), IPV4_DEVCONF_ARP_ANNOUNCE, 2);
    rtnl_link_inet_set_conf(changes.get(), IPV4_DEVCONF_RP_FILTER, 1);
  }
  Change(sock, ifindex, changes.get(), what);
}

void AddIpv4Address(const RouteSocket& sock, int ifindex, Ipv4 address, int prefix_length,
                    const std::string& what) {
  std::unique_ptr<rtnl_addr, RtnlAddrDeleter> addr(rtnl_addr_alloc());
  SITLNET_DEMAND(addr != nullptr);
  const uint32_t network_order = htonl(address.host_order);
  std::unique_ptr<nl_addr, AddrDeleter> local(nl_addr_build(AF_INET, &network_order, 4));
  nl_addr_set_prefixlen(local.get(), prefix_length);
  rtnl_addr_set_ifindex(addr.get(), ifindex);
  rtnl_addr_set_local(addr.get(), local.get());
  rtnl_addr_set_prefixlen(addr.get(), prefix_length);
  const int err = rtnl_addr_add(sock.get(), addr.get(), 0);
  if (err < 0) {
    throw Error(NlError(
        what + ": add address " + FormatIpv4(address) + "/" + std::to_string(prefix_length), err));
  }
}

void SetLinkUp(const RouteSocket& sock, int ifindex, const std::string& what) {
  LinkPtr changes(rtnl_link_alloc());
  SITLNET_DEMAND(changes != nullptr);
  rtnl_link_set_flags(changes.get(), IFF_UP);
  Change(sock, ifindex, changes.get(), what + ": set up");
}

void CreateVeth(const RouteSocket& sock, const std::string& root_name, uint32_t group,
                const std::string& peer_name, int peer_netns_fd, const std::string& what) {
  rtnl_link* raw = rtnl_link_veth_alloc();
  SITLNET_DEMAND(raw != nullptr);
  std::unique_ptr<rtnl_link, void (*)(rtnl_link*)> link(raw, rtnl_link_veth_release);
  rtnl_link_set_name(link.get(), root_name.c_str());
  rtnl_link_set_group(link.get(), group);
  LinkPtr peer(rtnl_link_veth_get_peer(link.get()));  // Takes a reference.
  rtnl_link_set_name(peer.get(), peer_name.c_str());
  rtnl_link_set_ns_fd(peer.get(), peer_netns_fd);
  const int err = rtnl_link_add(sock.get(), link.get(), NLM_F_CREATE | NLM_F_EXCL);
  if (err < 0) throw Error(NlError(what, err));
}

std::vector<LinkInfo> DumpLinks(const RouteSocket& sock) {
  nl_cache* raw_links = nullptr;
  int err = rtnl_link_alloc_cache(sock.get(), AF_UNSPEC, &raw_links);
  if (err < 0) throw Error(NlError("list links", err));
  std::unique_ptr<nl_cache, CacheDeleter> links(raw_links);
  nl_cache* raw_addrs = nullptr;
  err = rtnl_addr_alloc_cache(sock.get(), &raw_addrs);
  if (err < 0) throw Error(NlError("list addresses", err));
  std::unique_ptr<nl_cache, CacheDeleter> addrs(raw_addrs);

  std::vector<LinkInfo> result;
  for (nl_object* obj = nl_cache_get_first(links.get()); obj; obj = nl_cache_get_next(obj)) {
    auto* link = reinterpret_cast<rtnl_link*>(obj);
    LinkInfo info;
    info.name = rtnl_link_get_name(link);
    const char* kind = rtnl_link_get_type(link);
    const unsigned flags = rtnl_link_get_flags(link);
    info.kind = kind ? kind : ((flags & IFF_LOOPBACK) ? "loopback" : "");
    info.up = (flags & IFF_UP) != 0;
    info.txqueuelen = static_cast<int>(rtnl_link_get_txqlen(link));
    char text[64];
    if (nl_addr* mac = rtnl_link_get_addr(link)) info.mac = nl_addr2str(mac, text, sizeof text);
    const int ifindex = rtnl_link_get_ifindex(link);
    for (nl_object* a = nl_cache_get_first(addrs.get()); a; a = nl_cache_get_next(a)) {
      auto* addr = reinterpret_cast<rtnl_addr*>(a);
      if (rtnl_addr_get_ifindex(addr) != ifindex || rtnl_addr_get_family(addr) != AF_INET) {
        continue;
      }
      info.ipv4.push_back(nl_addr2str(rtnl_addr_get_local(addr), text, sizeof text));
    }
    result.push_back(std::move(info));
  }
  return result;
}

void RefuseRouterAdvertisements(const std::string& name, const std::string& what) {
  const std::string path = "/proc/sys/net/ipv6/conf/" + name + "/accept_ra";
  if (access("/proc/sys/net/ipv6", F_OK) != 0) return;  // No IPv6 on this host.
  if (const int err = WriteNetSysctl(path, "0"); err != 0) {
    throw Error(SystemErrorMessage(what + ": refuse IPv6 router advertisements (write \"" + path +
                                       "\": a robot could install routes in this namespace)",
                                   err));
  }
}

}  // namespace internal

std::vector<HostRoute> ReadHostRoutes() {
  internal::RouteSocket sock;
  nl_cache* raw = nullptr;
  const int err = rtnl_route_alloc_cache(sock.get(), AF_INET, 0, &raw);
  if (err < 0) throw Error(internal::NlError("read IPv4 routes", err));
  std::unique_ptr<nl_cache, internal::CacheDeleter> routes(raw);
  std::vector<HostRoute> result;
  for (nl_object* obj = nl_cache_get_first(routes.get()); obj; obj = nl_cache_get_next(obj)) {
    auto* route = reinterpret_cast<rtnl_route*>(obj);
    // The local table holds the host's own addresses and broadcasts, which
    // the main table's prefix routes already cover.
    if (rtnl_route_get_table(route) == RT_TABLE_LOCAL) continue;
    nl_addr* dst = rtnl_route_get_dst(route);
    HostRoute host_route;
    if (dst != nullptr && nl_addr_get_len(dst) == 4) {
      uint32_t network_order = 0;
      std::memcpy(&network_order, nl_addr_get_binary_addr(dst), 4);
      host_route.destination.length = static_cast<int>(nl_addr_get_prefixlen(dst));
      host_route.destination.network = Ipv4{ntohl(network_order) & host_route.destination.Mask()};
    }
    if (rtnl_route_get_nnexthops(route) > 0) {
      char name[IF_NAMESIZE] = "";
      const int ifindex = rtnl_route_nh_get_ifindex(rtnl_route_nexthop_n(route, 0));
      if (ifindex > 0 && if_indextoname(ifindex, name) != nullptr) host_route.device = name;
    }
    if (host_route.device.empty()) host_route.device = "(none)";
    result.push_back(std::move(host_route));
  }
  return result;
}

}  // namespace sitlnet::nns

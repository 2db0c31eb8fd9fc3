// Permanent IPv4 neighbour entries (static ARP) on a robot's wlan0.
#include <arpa/inet.h>
#include <linux/neighbour.h>
#include <netlink/netlink.h>
#include <netlink/route/neighbour.h>

#include <memory>

#include "nns/nns_internal.h"

namespace sitlnet::nns::internal {

void AddPermanentNeighbour(const RouteSocket& sock, int ifindex, Ipv4 address,
                           const MacAddress& mac, const std::string& what) {
  std::unique_ptr<rtnl_neigh, void (*)(rtnl_neigh*)> neigh(rtnl_neigh_alloc(), rtnl_neigh_put);
  SITLNET_DEMAND(neigh != nullptr);
  const uint32_t network_order = htonl(address.host_order);
  std::unique_ptr<nl_addr, void (*)(nl_addr*)> dst(nl_addr_build(AF_INET, &network_order, 4),
                                                   nl_addr_put);
  std::unique_ptr<nl_addr, void (*)(nl_addr*)> lladdr(
      nl_addr_build(AF_LLC, mac.bytes.data(), mac.bytes.size()), nl_addr_put);
  rtnl_neigh_set_ifindex(neigh.get(), ifindex);
  rtnl_neigh_set_family(neigh.get(), AF_INET);
  rtnl_neigh_set_dst(neigh.get(), dst.get());
  rtnl_neigh_set_lladdr(neigh.get(), lladdr.get());
  rtnl_neigh_set_state(neigh.get(), NUD_PERMANENT);
  const int err = rtnl_neigh_add(sock.get(), neigh.get(), NLM_F_CREATE | NLM_F_REPLACE);
  if (err < 0) {
    throw Error(what + ": add neighbour " + FormatIpv4(address) + " lladdr " + FormatMac(mac) +
                ": " + nl_geterror(err));
  }
}

}  // namespace sitlnet::nns::internal

// Accepting a fleet's node hosts: each must be one of the scenario's nodes, with exactly its
// robots, and come once.
#include "fleet/node_link.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>

#include "fleet/node_hello_check.h"

namespace sitlnet::fleet {
namespace {

// "10.88.0.5:40312", "[::1]:40312", or "a unix socket".
std::string PeerAddress(int fd) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    return "an unknown address";
  }
  char text[INET6_ADDRSTRLEN] = "";
  if (address.ss_family == AF_INET) {
    const auto& in = reinterpret_cast<const sockaddr_in&>(address);
    inet_ntop(AF_INET, &in.sin_addr, text, sizeof text);
    return std::string(text) + ":" + std::to_string(ntohs(in.sin_port));
  }
  if (address.ss_family == AF_INET6) {
    const auto& in6 = reinterpret_cast<const sockaddr_in6&>(address);
    inet_ntop(AF_INET6, &in6.sin6_addr, text, sizeof text);
    return "[" + std::string(text) + "]:" + std::to_string(ntohs(in6.sin6_port));
  }
  return "a unix socket";
}

}  // namespace

NodeLink::NodeLink(const Scenario& scenario, NodeSlice slice, coordinator::AcceptedPeer peer)
    : slice_(std::move(slice)),
      description_(DescribeNode(scenario, slice_)),
      address_(PeerAddress(peer.channel.fd())),
      connector_(std::move(peer.name), coordinator::Role::kNode, std::move(peer.channel),
                 std::move(*peer.hello.mutable_initial_poses()), description_) {}

std::vector<std::unique_ptr<NodeLink>> AcceptNodes(coordinator::Listener& listener,
                                                   const Scenario& scenario,
                                                   const std::vector<NodeSlice>& nodes,
                                                   coordinator::HandshakeExpectation expect,
                                                   const coordinator::WaitLimits& limits) {
  SITLNET_DEMAND(!nodes.empty());
  for (const NodeSlice& node : nodes) SITLNET_DEMAND(!node.robots.empty());
  expect.role = coordinator::Role::kNode;
  expect.refuse_hello = [&scenario, &nodes](const proto::coord::Hello& hello) {
    return RefuseNodeHello(scenario, nodes, hello);
  };
  std::vector<std::unique_ptr<NodeLink>> links(nodes.size());
  size_t joined = 0;
  const auto take = [&](coordinator::AcceptedPeer peer) {
    // RefuseNodeHello found the name among `nodes`.
    const size_t index = static_cast<size_t>(
        std::ranges::find(nodes, peer.hello.connector_name(), &NodeSlice::name) - nodes.begin());
    auto link = std::make_unique<NodeLink>(scenario, nodes[index], std::move(peer));
    if (links[index]) {
      const std::string what = "two nodes claim robot '" +
                               scenario.robots[nodes[index].robots.front()].name + "': node '" +
                               nodes[index].name + "' from " + links[index]->address() +
                               " and node '" + nodes[index].name + "' from " + link->address();
      link->connector().Stop(what);
      throw Error(what);
    }
    links[index] = std::move(link);
    return ++joined == nodes.size();
  };
  const auto missing = [&] {
    std::string absent;
    for (size_t i = 0; i < nodes.size(); ++i) {
      if (!links[i]) absent += (absent.empty() ? "" : ", ") + DescribeNode(scenario, nodes[i]);
    }
    return absent + " did not connect";
  };
  try {
    if (!coordinator::AcceptUntil(listener, expect, limits, take, missing)) return {};
  } catch (const Error& e) {
    for (const std::unique_ptr<NodeLink>& link : links) {
      if (link) link->connector().Stop(e.what());
    }
    throw;
  }
  return links;
}

}  // namespace sitlnet::fleet

#include "view/listen_address.h"

#include <arpa/inet.h>

#include <charconv>

#include "common/common.h"

namespace sitlnet::view {

bool IsLoopback(const std::string& host) {
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

ListenAddress ParseListenAddress(const std::string& text, bool allow_remote) {
  const std::string where = "listen address \"" + text + "\"";
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) throw Error(where + ": not ADDR:PORT");
  ListenAddress address;
  address.host = text.substr(0, colon);
  if (address.host.size() >= 2 && address.host.front() == '[' && address.host.back() == ']') {
    address.host = address.host.substr(1, address.host.size() - 2);
  }
  const std::string port = text.substr(colon + 1);
  const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), address.port);
  if (port.empty() || error != std::errc() || end != port.data() + port.size() ||
      address.port < 0 || address.port > 65535) {
    throw Error(where + ": port \"" + port + "\" is not 0-65535");
  }
  in_addr v4{};
  in6_addr v6{};
  if (inet_pton(AF_INET, address.host.c_str(), &v4) != 1 &&
      inet_pton(AF_INET6, address.host.c_str(), &v6) != 1) {
    throw Error(where + ": \"" + address.host + "\" is not a numeric IPv4 or IPv6 address");
  }
  if (!allow_remote && !IsLoopback(address.host)) {
    throw Error(where + ": not a loopback address; anyone who reaches it sees the run "
                "(add --allow-remote to serve it there)");
  }
  return address;
}

std::string HostPort(const ListenAddress& address) {
  const bool v6 = address.host.find(':') != std::string::npos;
  return (v6 ? "[" + address.host + "]" : address.host) + ":" + std::to_string(address.port);
}

std::string PageUrl(const ListenAddress& address) { return "http://" + HostPort(address) + "/"; }

}  // namespace sitlnet::view

// Where `sitlnet view` listens: "ADDR:PORT", loopback unless the user allows another address.
#ifndef SITLNET_VIEW_LISTEN_ADDRESS_H_
#define SITLNET_VIEW_LISTEN_ADDRESS_H_

#include <string>

#include "common/common.h"

namespace sitlnet::view {

// The address could not be bound (in use, not an address of this host): a refused system
// operation, not bad input.
class ListenError : public Error {
 public:
  using Error::Error;
};

struct ListenAddress {
  std::string host;  // A numeric IPv4 or IPv6 address, without brackets.
  int port = 0;      // 0: any free port (the kernel chooses).
};

inline constexpr char kDefaultListen[] = "127.0.0.1:7300";

// Parses "ADDR:PORT" ("[ADDR]:PORT" for IPv6). Throws Error naming the text and the rule: a
// numeric address, a port 0-65535, and a loopback address unless `allow_remote`.
ListenAddress ParseListenAddress(const std::string& text, bool allow_remote);

// True for 127.0.0.0/8 and ::1.
bool IsLoopback(const std::string& host);

// "HOST:PORT" ("[HOST]:PORT" for IPv6).
std::string HostPort(const ListenAddress& address);

// "http://HOST:PORT/" (brackets around an IPv6 host).
std::string PageUrl(const ListenAddress& address);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_LISTEN_ADDRESS_H_

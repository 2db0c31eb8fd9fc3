#include "common/common.h"

#include <arpa/inet.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace sitlnet {

void DemandFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "sitlnet: internal error: %s:%d: failed condition '%s'\n", file, line,
               condition);
  std::abort();
}

std::string SystemErrorMessage(std::string_view what, int err) {
  return std::string(what) + ": " + std::strerror(err);
}

TimeNs MonotonicNowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return TimeNs{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

std::optional<Ipv4> ParseIpv4(std::string_view text) {
  // inet_pton accepts exactly dotted-quad decimal, which is what we document.
  std::string copy(text);
  in_addr addr{};
  if (inet_pton(AF_INET, copy.c_str(), &addr) != 1) return std::nullopt;
  return Ipv4{ntohl(addr.s_addr)};
}

std::string FormatIpv4(Ipv4 address) {
  char text[INET_ADDRSTRLEN];
  in_addr addr{htonl(address.host_order)};
  inet_ntop(AF_INET, &addr, text, sizeof text);
  return text;
}

bool Ipv4Prefix::Overlaps(const Ipv4Prefix& other) const {
  const int shorter = length < other.length ? length : other.length;
  const uint32_t mask = shorter == 0 ? 0 : ~uint32_t{0} << (32 - shorter);
  return (network.host_order & mask) == (other.network.host_order & mask);
}

std::optional<Ipv4Prefix> ParseIpv4Prefix(std::string_view text) {
  const size_t slash = text.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  const auto address = ParseIpv4(text.substr(0, slash));
  const std::string length_text(text.substr(slash + 1));
  if (!address || length_text.empty() || length_text.size() > 2) return std::nullopt;
  for (char c : length_text) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  const int length = std::atoi(length_text.c_str());
  if (length > 32) return std::nullopt;
  Ipv4Prefix prefix{*address, length};
  if ((address->host_order & prefix.Mask()) != address->host_order) return std::nullopt;
  return prefix;
}

std::string FormatIpv4Prefix(const Ipv4Prefix& prefix) {
  return FormatIpv4(prefix.network) + "/" + std::to_string(prefix.length);
}

std::string FormatMac(const MacAddress& mac) {
  char text[18];
  std::snprintf(text, sizeof text, "%02x:%02x:%02x:%02x:%02x:%02x", mac.bytes[0], mac.bytes[1],
                mac.bytes[2], mac.bytes[3], mac.bytes[4], mac.bytes[5]);
  return text;
}

MacAddress RobotMac(int index) {
  MacAddress mac{{0x02, 0x00, 0x00, 0x00, static_cast<uint8_t>((index >> 8) & 0xff),
                  static_cast<uint8_t>(index & 0xff)}};
  return mac;
}

bool IsInvokingUser(unsigned owner) {
  if (owner == geteuid()) return true;
  const char* sudo_uid = std::getenv("SUDO_UID");
  return geteuid() == 0 && sudo_uid != nullptr && std::to_string(owner) == sudo_uid;
}

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
  if (this != &other) Reset(other.Release());
  return *this;
}

int UniqueFd::Release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

void UniqueFd::Reset(int fd) {
  if (fd_ >= 0) close(fd_);
  fd_ = fd;
}

}  // namespace sitlnet

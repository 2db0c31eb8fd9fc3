// The --gcs forms: "udp:HOST:PORT" and "tcp-listen:PORT".
#include <arpa/inet.h>

#include <string>

#include "gcs_link/gcs_link.h"

namespace sitlnet::gcs {
namespace {

constexpr const char* kForms = "expected udp:HOST:PORT (HOST an IPv4 address) or tcp-listen:PORT";

// A port 1..65535 written in decimal, or nullopt.
std::optional<uint16_t> ParsePort(const std::string& text) {
  if (text.empty() || text.size() > 5 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  const int port = std::stoi(text);
  if (port < 1 || port > 65535) return std::nullopt;
  return static_cast<uint16_t>(port);
}

}  // namespace

GcsEndpoint ParseGcsEndpoint(const std::string& text) {
  const auto refuse = [&text](const std::string& why) -> Error {
    return Error("--gcs " + text + ": " + why);
  };
  GcsEndpoint endpoint;
  endpoint.text = text;
  constexpr std::string_view kUdp = "udp:", kTcpListen = "tcp-listen:";
  if (text.rfind(kTcpListen, 0) == 0) {
    const auto port = ParsePort(text.substr(kTcpListen.size()));
    if (!port) throw refuse("the port must be in [1, 65535]");
    endpoint.kind = GcsEndpoint::Kind::kTcpListen;
    endpoint.port = *port;
    return endpoint;
  }
  if (text.rfind(kUdp, 0) != 0) throw refuse(kForms);
  const std::string rest = text.substr(kUdp.size());
  const size_t colon = rest.rfind(':');
  if (colon == std::string::npos) throw refuse(kForms);
  endpoint.host = rest.substr(0, colon);
  in_addr address{};
  if (inet_pton(AF_INET, endpoint.host.c_str(), &address) != 1) {
    throw refuse("'" + endpoint.host + "' is not an IPv4 address");
  }
  const auto port = ParsePort(rest.substr(colon + 1));
  if (!port) throw refuse("the port must be in [1, 65535]");
  endpoint.port = *port;
  return endpoint;
}

GcsEndpoint DefaultGcsEndpoint() {
  return ParseGcsEndpoint("udp:127.0.0.1:" + std::to_string(kGcsUdpPort));
}

}  // namespace sitlnet::gcs

#include "gcs_link/station_socket.h"

#include <sys/socket.h>

#include <cerrno>

namespace sitlnet::gcs {
namespace {

constexpr size_t kMaxVehicles = 256;  // Senders beyond this are relayed but not answered.
constexpr size_t kMaxDatagramBytes = 65536;

bool SameSender(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}

}  // namespace

StationSocket::StationSocket(const std::string& netns, uint16_t port) {
  const std::string what = "UDP port " + std::to_string(port) + " in netns \"" + netns + "\"";
  {
    nns::ScopedNetns inside(netns);
    socket_.Reset(socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  }
  if (!socket_.valid()) throw Error(SystemErrorMessage("socket for " + what, errno));
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_port = htons(port);
  if (bind(socket_.get(), reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) {
    throw Error(SystemErrorMessage("bind " + what, errno));
  }
}

bool StationSocket::Receive(std::vector<uint8_t>* buffer, GcsRelayCounters* counters) {
  buffer->resize(kMaxDatagramBytes);
  sockaddr_in from{};
  socklen_t from_size = sizeof from;
  const ssize_t n = recvfrom(socket_.get(), buffer->data(), buffer->size(), MSG_DONTWAIT,
                             reinterpret_cast<sockaddr*>(&from), &from_size);
  if (n < 0) return false;
  buffer->resize(static_cast<size_t>(n));
  ++counters->from_vehicles;
  bool known = false;
  for (const sockaddr_in& vehicle : vehicles_) known = known || SameSender(vehicle, from);
  if (!known && vehicles_.size() < kMaxVehicles) {
    vehicles_.push_back(from);
    counters->vehicle_addresses = vehicles_.size();
  }
  return true;
}

void StationSocket::SendToVehicles(const uint8_t* data, size_t size, GcsRelayCounters* counters) {
  for (const sockaddr_in& vehicle : vehicles_) {
    if (sendto(socket_.get(), data, size, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&vehicle),
               sizeof vehicle) >= 0) {
      ++counters->to_vehicles;
    } else {
      ++counters->to_vehicles_failed;
    }
  }
}

}  // namespace sitlnet::gcs

#include "gcs_link/station_socket.h"

#include <sys/socket.h>

#include <cerrno>

#include "gcs_link/frame_stream.h"
#include "gcs_link/message_target.h"
#include "mavlink/mavlink.h"

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
  last_sender_ = Ipv4{ntohl(from.sin_addr.s_addr)};
  bool known = false;
  for (const sockaddr_in& vehicle : vehicles_) known = known || SameSender(vehicle, from);
  if (!known && vehicles_.size() < kMaxVehicles) {
    vehicles_.push_back(from);
    counters->vehicle_addresses = vehicles_.size();
  }
  ForEachFrame(buffer->data(), buffer->size(), [&](const uint8_t* frame, size_t /*bytes*/) {
    const uint8_t system = frame[0] == mavlink::kMagicV1 ? frame[3] : frame[5];
    std::vector<sockaddr_in>& senders = senders_of_system_[system];
    for (const sockaddr_in& sender : senders) {
      if (SameSender(sender, from)) return;
    }
    if (senders.size() < kMaxVehicles) senders.push_back(from);
  });
  return true;
}

void StationSocket::SendToVehicles(const uint8_t* frames, size_t size, GcsRelayCounters* counters) {
  ForEachFrame(frames, size, [&](const uint8_t* frame, size_t bytes) {
    const std::optional<uint8_t> target = TargetSystem(frame);
    const auto routed =
        target && *target != 0 ? senders_of_system_.find(*target) : senders_of_system_.end();
    if (routed != senders_of_system_.end()) {
      ++counters->to_vehicles_routed;
      for (const sockaddr_in& vehicle : routed->second) SendTo(vehicle, frame, bytes, counters);
      return;
    }
    for (const sockaddr_in& vehicle : vehicles_) SendTo(vehicle, frame, bytes, counters);
  });
}

void StationSocket::SendTo(const sockaddr_in& vehicle, const uint8_t* frame, size_t bytes,
                           GcsRelayCounters* counters) {
  if (sendto(socket_.get(), frame, bytes, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&vehicle),
             sizeof vehicle) >= 0) {
    ++counters->to_vehicles;
  } else {
    ++counters->to_vehicles_failed;
  }
}

}  // namespace sitlnet::gcs

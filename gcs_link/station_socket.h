// The relay's socket in the ground station's namespace: where the vehicles' MAVLink arrives over
// the simulated radio, and whence the GCS's datagrams leave for every vehicle heard.
#ifndef SITLNET_GCS_LINK_STATION_SOCKET_H_
#define SITLNET_GCS_LINK_STATION_SOCKET_H_

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gcs_link/gcs_link.h"
#include "nns/nns.h"

namespace sitlnet::gcs {

class StationSocket {
 public:
  // Binds UDP `port` on every address of namespace `netns` (entered by the calling thread for the
  // call only). Throws Error naming the namespace, the port and the reason.
  StationSocket(const std::string& netns, uint16_t port);
  int fd() const { return socket_.get(); }
  // Reads one datagram into `buffer` (resized to it) and remembers its sender as a vehicle;
  // false when none is waiting.
  bool Receive(std::vector<uint8_t>* buffer, GcsRelayCounters* counters);
  // Sends each frame of `frames` (whole frames) as a datagram of its own, as mavlink-router
  // routes: a frame whose target system (message_target.h) has been heard goes to that system's
  // senders only; a broadcast, a message without a target, or a target not heard yet goes to
  // every vehicle heard so far (a vehicle ignores messages for other system ids).
  // The sender of the datagram Receive read last (its IPv4 address).
  Ipv4 last_sender() const { return last_sender_; }
  void SendToVehicles(const uint8_t* frames, size_t size, GcsRelayCounters* counters);

 private:
  void SendTo(const sockaddr_in& vehicle, const uint8_t* frame, size_t bytes,
              GcsRelayCounters* counters);

  UniqueFd socket_;
  std::vector<sockaddr_in> vehicles_;
  Ipv4 last_sender_;
  std::map<uint8_t, std::vector<sockaddr_in>> senders_of_system_;  // By MAVLink system id.
};

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_STATION_SOCKET_H_

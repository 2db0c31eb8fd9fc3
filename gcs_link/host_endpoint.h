// The host's side of the relay, one kind per GcsEndpoint::Kind behind one interface: what a GCS
// endpoint polls, reads and is sent.
#ifndef SITLNET_GCS_LINK_HOST_ENDPOINT_H_
#define SITLNET_GCS_LINK_HOST_ENDPOINT_H_

#include <poll.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "gcs_link/gcs_link.h"

namespace sitlnet::gcs {

// Takes whole MAVLink frames a GCS sent (frame_stream.h), for the vehicles.
using GcsBytesSink = std::function<void(const uint8_t* data, size_t size)>;

class HostEndpoint {
 public:
  virtual ~HostEndpoint() = default;
  // Appends the fds to poll now, with their events.
  virtual void AppendPollFds(std::vector<pollfd>* fds) const = 0;
  // Handles `ready` if it is one of this endpoint's fds (else returns false): reads what the GCS
  // sent, its whole frames into `to_vehicles`, accepts or drops clients, drains ICMP errors. Never
  // throws.
  virtual bool HandleReady(const pollfd& ready, const GcsBytesSink& to_vehicles,
                           GcsRelayCounters* counters) = 0;
  // Sends one datagram of the vehicles to the GCS; what it cannot take is counted, never fatal.
  virtual void SendToGcs(const uint8_t* data, size_t size, GcsRelayCounters* counters) = 0;
};

// Binds the endpoint's socket in the calling thread's namespace. Throws Error naming the
// endpoint and the system error.
std::unique_ptr<HostEndpoint> MakeUdpEndpoint(const GcsEndpoint& endpoint);
std::unique_ptr<HostEndpoint> MakeTcpListenEndpoint(const GcsEndpoint& endpoint);

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_HOST_ENDPOINT_H_

// Per vehicle (MAVLink system id): messages heard, sequence gaps and the latest autopilot
// HEARTBEAT, from the frames that reached the station.
#ifndef SITLNET_GCS_LINK_VEHICLE_TALLY_H_
#define SITLNET_GCS_LINK_VEHICLE_TALLY_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "gcs_link/gcs_link.h"

namespace sitlnet::gcs {

class VehicleTally {
 public:
  // Counts one whole frame (mavlink::FrameBytes said so), from a datagram sent by `sender`.
  void Count(const uint8_t* frame, size_t bytes, Ipv4 sender = {});
  // Every vehicle heard, by system id.
  std::vector<VehicleCounters> vehicles() const;

 private:
  struct Vehicle {
    VehicleCounters counters;
    std::array<int, 256> last_sequence;  // Per component id; -1: none yet.
  };
  std::map<uint8_t, Vehicle> vehicles_;
};

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_VEHICLE_TALLY_H_

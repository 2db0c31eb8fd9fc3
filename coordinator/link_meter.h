// What a link to a connector on another host costs, as the coordinator's end measures it: each
// round trip's wall time (START sent until its END is read) and the bytes each way, as they
// cross the socket (frame header, body and tag). For a fleet's node links (summary.json
// "fleet_links", docs/run.md).
#ifndef SITLNET_COORDINATOR_LINK_METER_H_
#define SITLNET_COORDINATOR_LINK_METER_H_

#include <cstdint>
#include <vector>

#include "common/common.h"

namespace sitlnet::coordinator {

// A link's round trips so far: those whose END was read (an interrupted one does not count).
struct LinkStats {
  int64_t round_trips = 0;
  // Nearest-rank percentiles of the round trips' wall time; 0 without round trips.
  TimeNs round_trip_p50_ns = 0, round_trip_p99_ns = 0, round_trip_max_ns = 0;
  int64_t bytes_down = 0;  // Sent to the peer: the STARTs.
  int64_t bytes_up = 0;    // Received from it: what answered them (CommandsCollected, END).

  // Means per round trip; 0 without round trips.
  double BytesDownPerRoundTrip() const { return PerRoundTrip(bytes_down); }
  double BytesUpPerRoundTrip() const { return PerRoundTrip(bytes_up); }

 private:
  double PerRoundTrip(int64_t bytes) const {
    return round_trips > 0 ? static_cast<double>(bytes) / static_cast<double>(round_trips) : 0;
  }
};

// Counts as the iterations go: a clock reading and a few additions per message, and 8 bytes
// per round trip kept for the percentiles (2.9 MB per simulated hour at 10 ms iterations).
class LinkMeter {
 public:
  // START of a round trip sent at `now_ns`, in `bytes` on the socket.
  void StartSent(TimeNs now_ns, uint64_t bytes) {
    start_ns_ = now_ns;
    pending_down_ = bytes;
    pending_up_ = 0;
  }
  // A message of the answer received, in `bytes`.
  void Received(uint64_t bytes) { pending_up_ += bytes; }
  // The round trip's END read at `now_ns`: it counts from now on.
  void EndReceived(TimeNs now_ns) {
    round_trips_ns_.push_back(now_ns - start_ns_);
    bytes_down_ += pending_down_;
    bytes_up_ += pending_up_;
    pending_down_ = pending_up_ = 0;
  }
  LinkStats Stats() const;

 private:
  std::vector<TimeNs> round_trips_ns_;
  TimeNs start_ns_ = 0;
  uint64_t pending_down_ = 0, pending_up_ = 0;  // Of the round trip under way.
  uint64_t bytes_down_ = 0, bytes_up_ = 0;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_LINK_METER_H_

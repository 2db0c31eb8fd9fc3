#include "coordinator/link_meter.h"

#include "coordinator/metrics.h"

namespace sitlnet::coordinator {

LinkStats LinkMeter::Stats() const {
  LinkStats stats;
  stats.round_trips = static_cast<int64_t>(round_trips_ns_.size());
  stats.bytes_down = static_cast<int64_t>(bytes_down_);
  stats.bytes_up = static_cast<int64_t>(bytes_up_);
  // Doubles hold every nanosecond count below 2^53 (104 days) exactly.
  const Distribution distribution =
      Distribute(std::vector<double>(round_trips_ns_.begin(), round_trips_ns_.end()));
  stats.round_trip_p50_ns = static_cast<TimeNs>(distribution.p50);
  stats.round_trip_p99_ns = static_cast<TimeNs>(distribution.p99);
  stats.round_trip_max_ns = static_cast<TimeNs>(distribution.max);
  return stats;
}

}  // namespace sitlnet::coordinator

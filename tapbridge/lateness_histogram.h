// A histogram of lateness (how long after its due instant something happened), for realtime
// pacing: the bridge's delivery writes, and a fleet's frames and writes across hosts.
#ifndef SITLNET_TAPBRIDGE_LATENESS_HISTOGRAM_H_
#define SITLNET_TAPBRIDGE_LATENESS_HISTOGRAM_H_

#include <algorithm>
#include <cmath>
#include <vector>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

// Lateness histogram: 1 µs buckets up to 100 ms, the last bucket open-ended.
// Fixed memory, O(1) per delivery, percentiles to the microsecond.
class LatenessHistogram {
 public:
  void Add(TimeNs lateness_ns) {
    if (lateness_ns < 0) lateness_ns = 0;
    const size_t bucket = std::min<size_t>(lateness_ns / kNsPerUs, kBuckets - 1);
    ++buckets_[bucket];
    ++count_;
    max_ns_ = std::max(max_ns_, lateness_ns);
  }
  LatenessStats Stats() const {
    LatenessStats stats;
    stats.count = count_;
    stats.max_ns = max_ns_;
    stats.p50_ns = Quantile(0.5);
    stats.p99_ns = Quantile(0.99);
    return stats;
  }
  void Clear() {
    std::fill(buckets_.begin(), buckets_.end(), 0);
    count_ = 0;
    max_ns_ = 0;
  }

 private:
  static constexpr size_t kBuckets = 100000;
  TimeNs Quantile(double q) const {
    if (count_ == 0) return 0;
    const uint64_t rank = static_cast<uint64_t>(std::ceil(q * count_));
    uint64_t seen = 0;
    for (size_t i = 0; i < kBuckets; ++i) {
      seen += buckets_[i];
      if (seen >= rank) return std::min<TimeNs>((i + 1) * kNsPerUs, max_ns_);  // Upper edge.
    }
    return max_ns_;
  }
  std::vector<uint64_t> buckets_ = std::vector<uint64_t>(kBuckets);
  uint64_t count_ = 0;
  TimeNs max_ns_ = 0;
};

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_LATENESS_HISTOGRAM_H_

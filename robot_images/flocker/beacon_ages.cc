#include "robot_images/flocker/beacon_ages.h"

#include <algorithm>

namespace sitlnet::flocker {

std::string BeaconAges::TakeSummaryMs() {
  if (ages_ns_.empty()) return "-";
  std::sort(ages_ns_.begin(), ages_ns_.end());
  const int64_t median_ns = ages_ns_[(ages_ns_.size() - 1) / 2];
  const int64_t max_ns = ages_ns_.back();
  ages_ns_.clear();
  constexpr int64_t kNsPerMs = 1'000'000;
  return std::to_string(median_ns / kNsPerMs) + "/" + std::to_string(max_ns / kNsPerMs);
}

}  // namespace sitlnet::flocker

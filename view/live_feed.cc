#include "view/live_feed.h"

namespace sitlnet::view {

void LiveFeed::Poses(TimeNs time_ns, const std::vector<runner::LivePose>& poses) {
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) {
    ++skipped_;
    return;
  }
  shared_.time_ns = time_ns;
  shared_.poses = poses;  // Same size every time: no allocation after the first.
  shared_.trails.resize(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    std::vector<TrailPoint>& trail = shared_.trails[i];
    if (!trail.empty() && time_ns < trail.back().time_ns + kTrailPeriodNs) continue;
    if (trail.size() == kTrailPoints) trail.erase(trail.begin());
    trail.push_back({time_ns, poses[i].x_m, poses[i].y_m});
  }
}

void LiveFeed::Links(int64_t second, const std::vector<runner::LinkRow>& rows) {
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) {
    ++skipped_;
    return;
  }
  shared_.link_second = second;
  shared_.links = rows;
}

LiveSnapshot LiveFeed::Snapshot() const {
  std::lock_guard lock(mutex_);
  LiveSnapshot copy = shared_;
  copy.skipped_updates = skipped_;
  return copy;
}

}  // namespace sitlnet::view

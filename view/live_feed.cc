#include "view/live_feed.h"

namespace sitlnet::view {

template <typename Update>
void LiveFeed::TryUpdate(Update&& update) {
  const TimeNs begin_ns = MonotonicNowNs();
  {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (lock.owns_lock()) {
      update(shared_);
    } else {
      ++skipped_;
    }
  }
  ++updates_;
  spent_ns_ += MonotonicNowNs() - begin_ns;
}

void LiveFeed::Poses(TimeNs time_ns, const std::vector<run_formats::LivePose>& poses) {
  TryUpdate([&](LiveSnapshot& shared) {
    shared.time_ns = time_ns;
    shared.poses = poses;  // Same size every time: no allocation after the first.
    shared.trails.resize(poses.size());
    for (size_t i = 0; i < poses.size(); ++i) {
      std::vector<TrailPoint>& trail = shared.trails[i];
      if (!trail.empty() && time_ns < trail.back().time_ns + kTrailPeriodNs) continue;
      if (trail.size() == kTrailPoints) trail.erase(trail.begin());
      trail.push_back({time_ns, poses[i].x_m, poses[i].y_m});
    }
  });
}

void LiveFeed::Links(int64_t second, const std::vector<run_formats::LinkRow>& rows) {
  TryUpdate([&](LiveSnapshot& shared) {
    shared.link_second = second;
    shared.links = rows;
  });
}

void LiveFeed::Components(TimeNs time_ns, int components, const std::vector<int>& component_of) {
  TryUpdate([&](LiveSnapshot& shared) {
    shared.components_time_ns = time_ns;
    if (shared.connectivity.size() == kTimelineChanges) {
      shared.connectivity.erase(shared.connectivity.begin());
    }
    AppendIfChanged(time_ns, components, component_of, &shared.connectivity);
  });
}

void LiveFeed::Timing(const run_formats::SecondTiming& second) {
  TryUpdate([&](LiveSnapshot& shared) {
    if (shared.timing.size() == kTimingSeconds) shared.timing.erase(shared.timing.begin());
    shared.timing.push_back(second);
  });
}

void LiveFeed::Vehicles(TimeNs time_ns, const std::vector<run_formats::LiveVehicle>& vehicles) {
  TryUpdate([&](LiveSnapshot& shared) {
    shared.vehicles_time_ns = time_ns;
    shared.vehicles = vehicles;
  });
}

LiveSnapshot LiveFeed::Snapshot() const {
  std::lock_guard lock(mutex_);
  LiveSnapshot copy = shared_;
  copy.skipped_updates = skipped_;
  return copy;
}

}  // namespace sitlnet::view

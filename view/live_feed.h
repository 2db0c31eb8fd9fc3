// What the live view shows of a running run: the latest poses, a trail per robot, the latest
// second's links, the timeline (connectivity components, timing per second), and what the GCS
// relay heard of each vehicle. The run's
// threads write it through run_formats::LiveSink without ever waiting: an update that finds the
// server reading is skipped (and counted).
#ifndef SITLNET_VIEW_LIVE_FEED_H_
#define SITLNET_VIEW_LIVE_FEED_H_

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

#include "run_formats/run_formats.h"
#include "view/timeline_json.h"

namespace sitlnet::view {

struct TrailPoint {
  TimeNs time_ns = 0;
  double x_m = 0, y_m = 0;
};

struct LiveSnapshot {
  TimeNs time_ns = -1;  // Of `poses`; -1 before the first sample.
  std::vector<run_formats::LivePose> poses;
  std::vector<std::vector<TrailPoint>> trails;
  int64_t link_second = -1;  // Of `links`; -1 before the first whole second.
  std::vector<run_formats::LinkRow> links;
  TimeNs components_time_ns = -1;  // Of the latest connectivity sample; -1 before the first.
  std::vector<ComponentsChange> connectivity;  // Where the components changed, the last ones.
  std::vector<run_formats::SecondTiming> timing;  // The last seconds' timing.
  TimeNs vehicles_time_ns = -1;  // Of `vehicles`; -1 before the first (or without a GCS relay).
  std::vector<run_formats::LiveVehicle> vehicles;  // What the GCS relay heard, by system id.
  uint64_t skipped_updates = 0;
};

class LiveFeed final : public run_formats::LiveSink {
 public:
  // A trail keeps a point every kTrailPeriodNs of simulated time, the last kTrailPoints of them.
  static constexpr TimeNs kTrailPeriodNs = 500 * kNsPerMs;
  static constexpr size_t kTrailPoints = 240;
  // The timeline keeps the last kTimelineChanges changes of components and kTimingSeconds
  // seconds of timing: a document of bounded size however long the run.
  static constexpr size_t kTimelineChanges = 1000;
  static constexpr size_t kTimingSeconds = 600;

  void Poses(TimeNs time_ns, const std::vector<run_formats::LivePose>& poses) override;
  void Links(int64_t second, const std::vector<run_formats::LinkRow>& rows) override;
  void Components(TimeNs time_ns, int components, const std::vector<int>& component_of) override;
  void Timing(const run_formats::SecondTiming& second) override;
  void Vehicles(TimeNs time_ns, const std::vector<run_formats::LiveVehicle>& vehicles) override;
  // The server's copy (it waits for the lock; the run's threads never do).
  LiveSnapshot Snapshot() const;

  // What the feed cost the run's threads: calls, those skipped, and the time spent in them.
  struct Cost {
    uint64_t updates = 0, skipped = 0;
    TimeNs spent_ns = 0;
  };
  Cost cost() const { return {updates_, skipped_, spent_ns_}; }

 private:
  // Runs `update` on the shared snapshot if the lock is free at once (else counts a skip): the
  // run's threads never wait for a reader. Counts the call and its time either way.
  template <typename Update>
  void TryUpdate(Update&& update);

  mutable std::mutex mutex_;
  LiveSnapshot shared_;  // Under mutex_.
  std::atomic<uint64_t> updates_{0}, skipped_{0};
  std::atomic<TimeNs> spent_ns_{0};
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_LIVE_FEED_H_

// Communication graph over time, from the medium's deliveries: robots i and j are linked at time
// t when either received a frame from the other within the window (t - window, t]. The graph's
// connected components show when a fleet splits and reunites (DANCERS paper, Fig. 6).
#ifndef SITLNET_RUNNER_CONNECTIVITY_H_
#define SITLNET_RUNNER_CONNECTIVITY_H_

#include <vector>

#include "common/common.h"
#include "runner/live_sink.h"

namespace sitlnet::runner {

struct ConnectivitySample {
  TimeNs time_ns = 0;
  int components = 0;
  std::vector<int> component_of;  // Per robot: its component's smallest robot index.
};

// Samples the graph every `sample_period_ns` (at sample_period_ns, 2 * sample_period_ns, ...)
// while deliveries stream in, so a run keeps no log of them in memory.
class ConnectivityTracker {
 public:
  ConnectivityTracker(int robots, TimeNs window_ns, TimeNs sample_period_ns);

  // A frame from robot `from` reached robot `to` at virtual time `time_ns`. Deliveries come in
  // time order (the medium's); a delivery at a sample's instant counts for that sample. Robots
  // out of range and self-deliveries are ignored.
  void Heard(TimeNs time_ns, int from, int to);

  // `sink` (may be null; outlives this) is told each sample as it is taken.
  void SetLiveSink(LiveSink* sink) { live_ = sink; }

  // Takes every sample up to `end_ns` (inclusive) and returns them all.
  std::vector<ConnectivitySample> Finish(TimeNs end_ns);

 private:
  void SampleUntilBefore(TimeNs time_ns);  // Takes the samples at instants < time_ns.
  int robots_;
  TimeNs window_ns_;
  TimeNs sample_period_ns_;
  TimeNs next_sample_ns_;
  std::vector<TimeNs> last_heard_;  // [a * robots + b], a < b: latest delivery either way.
  std::vector<ConnectivitySample> samples_;
  LiveSink* live_ = nullptr;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_CONNECTIVITY_H_

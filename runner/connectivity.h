// Communication graph over time, from the medium's delivery log: robots i and
// j are linked at time t when either received a frame from the other within
// the window (t - window, t]. The graph's connected components show when a
// fleet splits and reunites (DANCERS paper, Fig. 6).
#ifndef SITLNET_RUNNER_CONNECTIVITY_H_
#define SITLNET_RUNNER_CONNECTIVITY_H_

#include <vector>

#include "common/common.h"

namespace sitlnet::runner {

// One frame delivered by the medium from robot `from` to robot `to`.
struct LinkEvent {
  TimeNs time_ns = 0;
  int from = 0;
  int to = 0;
};

struct ConnectivitySample {
  TimeNs time_ns = 0;
  int components = 0;
  std::vector<int> component_of;  // Per robot: its component's smallest robot index.
};

// Samples the graph every `sample_period_ns` from `sample_period_ns` to
// `end_ns`. `events` must be sorted by time.
std::vector<ConnectivitySample> ConnectivityOverTime(int robots,
                                                     const std::vector<LinkEvent>& events,
                                                     TimeNs window_ns, TimeNs sample_period_ns,
                                                     TimeNs end_ns);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_CONNECTIVITY_H_

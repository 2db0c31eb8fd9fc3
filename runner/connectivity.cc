#include "runner/connectivity.h"

#include <algorithm>
#include <numeric>

namespace sitlnet::runner {
namespace {

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

std::vector<ConnectivitySample> ConnectivityOverTime(int robots,
                                                     const std::vector<LinkEvent>& events,
                                                     TimeNs window_ns, TimeNs sample_period_ns,
                                                     TimeNs end_ns) {
  SITLNET_DEMAND(robots >= 0 && window_ns > 0 && sample_period_ns > 0);
  // last_heard[i * robots + j]: latest delivery between i and j (either way).
  std::vector<TimeNs> last_heard(size_t(robots) * robots, -1);
  std::vector<ConnectivitySample> samples;
  size_t next_event = 0;
  for (TimeNs t = sample_period_ns; t <= end_ns; t += sample_period_ns) {
    for (; next_event < events.size() && events[next_event].time_ns <= t; ++next_event) {
      const LinkEvent& e = events[next_event];
      if (e.from < 0 || e.to < 0 || e.from >= robots || e.to >= robots || e.from == e.to) continue;
      const int a = std::min(e.from, e.to);
      const int b = std::max(e.from, e.to);
      last_heard[size_t(a) * robots + b] = e.time_ns;
    }
    std::vector<int> parent(robots);
    std::iota(parent.begin(), parent.end(), 0);
    for (int a = 0; a < robots; ++a) {
      for (int b = a + 1; b < robots; ++b) {
        const TimeNs heard = last_heard[size_t(a) * robots + b];
        if (heard >= 0 && t - heard < window_ns) {
          parent[std::max(Find(parent, a), Find(parent, b))] =
              std::min(Find(parent, a), Find(parent, b));
        }
      }
    }
    ConnectivitySample sample;
    sample.time_ns = t;
    sample.component_of.resize(robots);
    for (int i = 0; i < robots; ++i) {
      sample.component_of[i] = Find(parent, i);
      if (sample.component_of[i] == i) ++sample.components;
    }
    samples.push_back(std::move(sample));
  }
  return samples;
}

}  // namespace sitlnet::runner

#include "run_formats/run_formats.h"

#include <algorithm>
#include <numeric>

namespace sitlnet::run_formats {
namespace {

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

ConnectivityTracker::ConnectivityTracker(int robots, TimeNs window_ns, TimeNs sample_period_ns)
    : robots_(robots),
      window_ns_(window_ns),
      sample_period_ns_(sample_period_ns),
      next_sample_ns_(sample_period_ns),
      last_heard_(size_t(robots) * robots, -1) {
  SITLNET_DEMAND(robots >= 0 && window_ns > 0 && sample_period_ns > 0);
}

void ConnectivityTracker::Heard(TimeNs time_ns, int from, int to) {
  SampleUntilBefore(time_ns);
  if (from < 0 || to < 0 || from >= robots_ || to >= robots_ || from == to) return;
  const int a = std::min(from, to);
  const int b = std::max(from, to);
  last_heard_[size_t(a) * robots_ + b] = time_ns;
}

std::vector<ConnectivitySample> ConnectivityTracker::Finish(TimeNs end_ns) {
  SampleUntilBefore(end_ns + 1);
  return std::move(samples_);
}

void ConnectivityTracker::SampleUntilBefore(TimeNs time_ns) {
  for (; next_sample_ns_ < time_ns; next_sample_ns_ += sample_period_ns_) {
    const TimeNs t = next_sample_ns_;
    std::vector<int> parent(robots_);
    std::iota(parent.begin(), parent.end(), 0);
    for (int a = 0; a < robots_; ++a) {
      for (int b = a + 1; b < robots_; ++b) {
        const TimeNs heard = last_heard_[size_t(a) * robots_ + b];
        if (heard >= 0 && t - heard < window_ns_) {
          parent[std::max(Find(parent, a), Find(parent, b))] =
              std::min(Find(parent, a), Find(parent, b));
        }
      }
    }
    ConnectivitySample sample;
    sample.time_ns = t;
    sample.component_of.resize(robots_);
    for (int i = 0; i < robots_; ++i) {
      sample.component_of[i] = Find(parent, i);
      if (sample.component_of[i] == i) ++sample.components;
    }
    if (live_ != nullptr) live_->Components(t, sample.components, sample.component_of);
    samples_.push_back(std::move(sample));
  }
}

}  // namespace sitlnet::run_formats

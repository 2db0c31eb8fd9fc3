#include "tests/integration/served_on_time.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace sitlnet::nns::testing {
namespace {

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? NAN : values[values.size() / 2];
}

}  // namespace

ServedOnTime MeasureServedOnTime(const std::string& log) {
  std::vector<double> offsets_ms;                     // wall - virtual
  std::vector<double> early_phase_ms, late_phase_ms;  // the same, by phase in the iteration
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    double t = 0;
    long long wall_ns = 0;
    unsigned long long n = 0;
    double x = 0, y = 0, z = 0;
    if (std::sscanf(line.c_str(), "reply %llu t=%lf pos=%lf,%lf,%lf wall_ns=%lld", &n, &t, &x, &y,
                    &z, &wall_ns) == 6 &&
        t >= 0.5) {
      const double offset_ms = wall_ns / 1e6 - t * 1e3;
      offsets_ms.push_back(offset_ms);
      // Phase in the 10 ms iteration, from the microsecond-rounded virtual time.
      const double phase_ms = static_cast<double>(std::llround(t * 1e6) % 10000) / 1e3;
      if (phase_ms < 3) early_phase_ms.push_back(offset_ms);
      if (phase_ms >= 6) late_phase_ms.push_back(offset_ms);
    }
  }
  ServedOnTime served;
  served.observations = offsets_ms.size();
  served.early_phase = early_phase_ms.size();
  served.late_phase = late_phase_ms.size();
  served.phase_gap_ms = Median(early_phase_ms) - Median(late_phase_ms);
  if (!offsets_ms.empty()) {
    std::sort(offsets_ms.begin(), offsets_ms.end());
    const double median_ms = offsets_ms[offsets_ms.size() / 2];
    served.below_median_ms = median_ms - offsets_ms[offsets_ms.size() / 20];
    served.above_median_ms = offsets_ms[offsets_ms.size() * 19 / 20] - median_ms;
  }
  return served;
}

std::string ServedOnTime::Describe(const std::string& robot) const {
  char text[320];
  std::snprintf(text, sizeof text,
                "%s: %zu observations, wall - virtual: 5th percentile %.3f ms below the median, "
                "95th %.3f ms above; median of phases < 3 ms less that of phases >= 6 ms: "
                "%.3f ms (%zu and %zu observations)",
                robot.c_str(), observations, below_median_ms, above_median_ms, phase_gap_ms,
                early_phase, late_phase);
  return text;
}

}  // namespace sitlnet::nns::testing

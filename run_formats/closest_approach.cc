#include "run_formats/run_formats.h"

#include <cmath>

namespace sitlnet::run_formats {

void ClosestApproachTracker::Sample(TimeNs time_ns, const std::vector<double>& positions_m) {
  const int robots = static_cast<int>(positions_m.size() / 3);
  // Squared distances while searching: one square root per sample, not per pair. A fleet of 64
  // has 2016 pairs; at trajectories.csv's 10 Hz that is noise beside the physics.
  double best_m2 = closest_ ? closest_m2_ : INFINITY;
  int best_a = -1, best_b = -1;
  for (int a = 0; a < robots; ++a) {
    for (int b = a + 1; b < robots; ++b) {
      const double dx = positions_m[3 * b] - positions_m[3 * a];
      const double dy = positions_m[3 * b + 1] - positions_m[3 * a + 1];
      const double dz = positions_m[3 * b + 2] - positions_m[3 * a + 2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best_m2) {
        best_m2 = d2;
        best_a = a;
        best_b = b;
      }
    }
  }
  if (best_a < 0) return;
  closest_m2_ = best_m2;
  closest_ = ClosestApproach{std::sqrt(best_m2), time_ns, best_a, best_b};
}

}  // namespace sitlnet::run_formats

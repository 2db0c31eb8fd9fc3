// Comparing one robot's paths in two trajectories.csv within a distance bound, aligned at
// lift-off: PX4 arms at a time its threads decide (up to 0.7 s apart in two runs), so rows at the
// same simulated time compare a climbing vehicle with one still on the ground.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

struct PathRow {
  double time_s = 0, x_m = 0, y_m = 0, z_m = 0;
};

// Robot `robot`'s rows of trajectories.csv (time_s,robot,x_m,y_m,z_m,...), header skipped.
std::vector<PathRow> RowsOf(const std::string& csv, int robot) {
  std::vector<PathRow> rows;
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // header
  while (std::getline(lines, line)) {
    const char* at = line.c_str();
    char* end = nullptr;
    PathRow row;
    row.time_s = std::strtod(at, &end);
    if (*end != ',') continue;
    const long index = std::strtol(end + 1, &end, 10);
    if (*end != ',' || index != robot) continue;
    row.x_m = std::strtod(end + 1, &end);
    if (*end != ',') continue;
    row.y_m = std::strtod(end + 1, &end);
    if (*end != ',') continue;
    row.z_m = std::strtod(end + 1, &end);
    rows.push_back(row);
  }
  return rows;
}

// The first row 5 cm above the robot's height at 3 s (settled on its legs, not yet armed);
// nullopt if it never rises that far.
std::optional<size_t> LiftOff(const std::vector<PathRow>& path) {
  size_t settled = 0;
  while (settled + 1 < path.size() && path[settled].time_s < 3) ++settled;
  const double ground_m = path[settled].z_m;
  for (size_t i = settled; i < path.size(); ++i) {
    if (path[i].z_m >= ground_m + 0.05) return i;
  }
  return std::nullopt;
}

}  // namespace

std::optional<PathGap> ComparePathsFromLiftOff(const std::string& trajectories_a,
                                               const std::string& trajectories_b, int robot) {
  const std::vector<PathRow> paths[2] = {RowsOf(trajectories_a, robot),
                                         RowsOf(trajectories_b, robot)};
  if (paths[0].empty() || paths[1].empty()) return std::nullopt;
  const std::optional<size_t> lift_off[2] = {LiftOff(paths[0]), LiftOff(paths[1])};
  if (lift_off[0].has_value() != lift_off[1].has_value()) return std::nullopt;
  PathGap gap;
  size_t first[2] = {0, 0};
  for (int run = 0; run < 2; ++run) {
    if (!lift_off[run]) continue;
    first[run] = *lift_off[run];
    gap.lift_off_s[run] = paths[run][first[run]].time_s;
  }
  const size_t rows = std::min(paths[0].size() - first[0], paths[1].size() - first[1]);
  for (size_t k = 0; k < rows; ++k) {
    const PathRow& a = paths[0][first[0] + k];
    const PathRow& b = paths[1][first[1] + k];
    const double horizontal_m = std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
    gap.worst_horizontal_m = std::max(gap.worst_horizontal_m, horizontal_m);
    gap.worst_vertical_m = std::max(gap.worst_vertical_m, std::fabs(a.z_m - b.z_m));
    gap.worst_m = std::max(gap.worst_m, std::hypot(horizontal_m, a.z_m - b.z_m));
  }
  if (rows > 1) {
    gap.compared_s = paths[0][first[0] + rows - 1].time_s - paths[0][first[0]].time_s;
  }
  return gap;
}

}  // namespace sitlnet::verify

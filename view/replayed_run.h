// A finished run folder (docs/run.md) as `sitlnet view` replays it: the effective scenario
// (robots, obstacles), trajectories.csv, links.csv, losses.csv.gz, connectivity.csv, metrics.csv,
// summary.json, and the autopilots' modes heard in medium.pcap.
#ifndef SITLNET_VIEW_REPLAYED_RUN_H_
#define SITLNET_VIEW_REPLAYED_RUN_H_

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/common.h"
#include "run_formats/run_formats.h"
#include "scenario/scenario.h"
#include "view/air_modes.h"
#include "view/timeline_json.h"

namespace sitlnet::view {

// One row of trajectories.csv: time, robot, world ENU position and velocity.
struct PoseSample {
  TimeNs time_ns = 0;
  int robot = 0;
  double x_m = 0, y_m = 0, z_m = 0;
  double vx_m_s = 0, vy_m_s = 0, vz_m_s = 0;
};

// One row of links.csv; `delivery_ratio` < 0 where the file leaves it empty (only drops).
struct LinkSecond {
  int second = 0;
  int from = 0, to = 0;
  int frames = 0, delivered = 0;
  double delivery_ratio = -1;
  std::string main_cause;
  int main_cause_frames = 0;
  double rate_mbps = 0;  // 0: a links.csv older than these columns
  int mcs = -1;          // -1: not an HT/VHT link (links.csv's empty cell), or an older links.csv
};

// One row of losses.csv.gz: the fields a query selects on, and the row's cells as written.
struct LossRow {
  TimeNs time_ns = 0;
  int from = 0;
  int station = 0;
  std::vector<std::string> cells;
};

struct ReplayedRun {
  std::string run_dir;
  Scenario scenario;                  // scenario.textproto
  std::vector<PoseSample> poses;      // trajectories.csv, in file order
  std::vector<LinkSecond> links;      // links.csv, in file order
  std::vector<LossRow> losses;        // losses.csv.gz, in file order (by end of transmission)
  std::vector<ComponentsChange> connectivity;  // connectivity.csv's rows where they change
  std::vector<run_formats::SecondTiming> timing;  // metrics.csv per simulated second
  std::string summary_json;           // summary.json as written
  std::vector<ModeChange> modes;      // heard in medium.pcap (view/air_modes.h); none without it
  // Indices into `losses` per (from, station), in file order.
  std::map<std::pair<int, int>, std::vector<size_t>> losses_by_link;
};

// Reads every file of `run_dir`. Throws Error, one line naming the folder or file:line and
// what is wrong: a missing file (an unfinished run, one with --no-losses or --remote network),
// a header of another sitlnet version, a malformed row.
ReplayedRun LoadReplayedRun(const std::string& run_dir);

// The whole of the file at `path`. Throws Error naming it.
std::string ReadText(const std::string& path);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_REPLAYED_RUN_H_

// points.csv and summary.csv from the point folders' state (docs/sweep.md, "Results").
#ifndef SITLNET_SWEEP_RESULTS_CSV_H_
#define SITLNET_SWEEP_RESULTS_CSV_H_

#include <string>
#include <vector>

#include "sweep/sweep.h"

namespace sitlnet::sweep {

// Where a point stands, read from its folder.
struct PointState {
  enum Status { kFinished, kFailed, kNotRun } status = kNotRun;
  std::string reason;                          // kFailed: exit status and stderr's last line.
  std::vector<std::optional<double>> metrics;  // kFinished: one per metric.
};

// The state of `folder` (its summary.json and sweep-failure.txt), with `metrics` read.
PointState ReadPointState(const std::string& folder, const std::vector<std::string>& metrics);

// The file a failed point's reason is kept in, in its folder.
inline constexpr const char* kFailureFile = "sweep-failure.txt";

// Replaces `path` with `text`, never through a symbolic link (the sweep may run as root in a
// folder a user chose, as `sitlnet run` does; docs/run.md, "Run folder"). Throws Error.
void WriteWholeFile(const std::string& path, const std::string& text);

// Writes out_dir/points.csv and out_dir/summary.csv.
void WriteResults(const std::string& out_dir, const std::vector<SweepAxis>& axes,
                  const std::vector<SweepPoint>& points, const std::vector<PointState>& states,
                  const std::vector<std::string>& metrics);

}  // namespace sitlnet::sweep

#endif  // SITLNET_SWEEP_RESULTS_CSV_H_

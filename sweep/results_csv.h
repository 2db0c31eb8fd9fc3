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

// One combination's statistics of one metric: a row of summary.csv.
struct CombinationSummary {
  size_t first_point = 0;  // Its first point (the values are that point's).
  size_t metric = 0;       // Index into the metrics.
  SampleSummary stats;
};

// Every combination's statistics of every metric, in summary.csv's order.
std::vector<CombinationSummary> SummarizeCombinations(const std::vector<SweepPoint>& points,
                                                      const std::vector<PointState>& states,
                                                      size_t metrics);

// Writes out_dir/points.csv and out_dir/summary.csv.
void WriteResults(const std::string& out_dir, const std::vector<SweepAxis>& axes,
                  const std::vector<SweepPoint>& points, const std::vector<PointState>& states,
                  const std::vector<std::string>& metrics);

// Draws plot_<metric>_vs_<field>.png in out_dir with gnuplot for each metric and each field of
// more than one value: the mean against the field's values with the 95 % interval as bars, one
// line per combination of the other fields' values; out_dir/plots.gnuplot is the script.
// Returns the PNGs drawn; gnuplot missing or failing is a warning line in *warning.
std::vector<std::string> DrawPlots(const std::string& out_dir, const std::vector<SweepAxis>& axes,
                                   const std::vector<SweepPoint>& points,
                                   const std::vector<CombinationSummary>& rows,
                                   const std::vector<std::string>& metrics, std::string* warning);

}  // namespace sitlnet::sweep

#endif  // SITLNET_SWEEP_RESULTS_CSV_H_

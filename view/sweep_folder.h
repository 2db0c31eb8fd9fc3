// A sweep's folder (docs/sweep-reference.md) as `sitlnet view` shows it: its points.csv and
// summary.csv, served whole for the page to parse (RFC 4180, by d3-dsv), and the page to show.
#ifndef SITLNET_VIEW_SWEEP_FOLDER_H_
#define SITLNET_VIEW_SWEEP_FOLDER_H_

#include <string>

namespace sitlnet::view {

// The sweep's page, under the web folder (view/web/sweep.html).
inline constexpr char kSweepPage[] = "sweep.html";

// True when `dir` holds points.csv and no summary.json: a sweep's folder, not a run's.
bool IsSweepFolder(const std::string& dir);

// {"folder": DIR, "points_csv": TEXT, "summary_csv": TEXT}. Throws Error naming a missing or
// unreadable file (a sweep still running, or one collected with --point only).
std::string SweepJson(const std::string& dir);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_SWEEP_FOLDER_H_

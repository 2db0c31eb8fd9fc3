// The JSON documents the page reads (docs/view.md, "Endpoints"), built from a ReplayedRun.
#ifndef SITLNET_VIEW_REPLAY_JSON_H_
#define SITLNET_VIEW_REPLAY_JSON_H_

#include <string>

#include "common/common.h"
#include "view/replayed_run.h"

namespace sitlnet::view {

// /api/run: scenario name, run folder, live or replay, robots (index, name), obstacles (centre,
// size, yaw), the time covered (`end_ns`), and losses.csv.gz's columns.
std::string RunJson(const Scenario& scenario, const std::string& run_dir, TimeNs end_ns, bool live);
// The same for a replay: the time the trajectories cover.
std::string RunJson(const ReplayedRun& record);

// /api/trajectories: per robot, its samples as [time_s, x_m, y_m, z_m, speed_m_s].
std::string TrajectoriesJson(const ReplayedRun& record);

// /api/links: links.csv's rows as [second, from, to, frames, delivered, ratio|null,
// main_cause, main_cause_frames].
std::string LinksJson(const ReplayedRun& record);

// /api/timeline: {"connectivity", "timing"} (view/timeline_json.h) of the whole run.
std::string TimelineJson(const ReplayedRun& record);

// /api/modes: {"modes": [[time_s, robot, mode], ...]}, each robot's autopilot mode changes heard
// in medium.pcap (view/air_modes.h), in time order.
std::string ModesJson(const ReplayedRun& record);

// /api/gcs: {"vehicles": [...]} (view/gcs_vehicles.h), what the GCS relay heard of each vehicle
// by the run's end, from summary.json; an empty list for a run without a relay.
std::string GcsJson(const ReplayedRun& record);

// At most this many rows in a /api/frames answer (its `total` counts them all).
inline constexpr size_t kMaxFrameRows = 2000;

// /api/frames: losses.csv.gz's rows of transmissions by `from` that reached `station`, with
// time_ns in [end_ns - window_ns, end_ns) (links.csv's second when whole seconds), ordered by
// time_ns (stable: ties in file order).
std::string FramesJson(const ReplayedRun& record, int from, int station, TimeNs end_ns,
                       TimeNs window_ns);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_REPLAY_JSON_H_

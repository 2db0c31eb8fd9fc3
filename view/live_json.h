// /api/live: the live view's document, from a LiveFeed snapshot.
#ifndef SITLNET_VIEW_LIVE_JSON_H_
#define SITLNET_VIEW_LIVE_JSON_H_

#include <string>
#include <vector>

#include "view/air_modes.h"
#include "view/live_feed.h"

namespace sitlnet::view {

// {"time_s", "robots": [[time_s, x_m, y_m, z_m, speed_m_s] or null], "trails": [[[time_s, x_m,
// y_m], ...], ...], "link_second", "links": [links.csv rows as /api/links],
// "components_time_s", "connectivity", "timing" (view/timeline_json.h), "skipped_updates",
// "modes": each robot's latest autopilot mode change as [time_s, robot, mode], "gcs_time_s",
// "gcs": what the GCS relay heard of each vehicle (view/gcs_vehicles.h), [] without a relay}.
std::string LiveJson(const LiveSnapshot& snapshot, const std::vector<ModeChange>& modes);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_LIVE_JSON_H_

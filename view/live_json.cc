#include "view/live_json.h"

#include "view/gcs_vehicles.h"
#include "view/json_text.h"
#include "view/timeline_json.h"

namespace sitlnet::view {

std::string LiveJson(const LiveSnapshot& snapshot, const std::vector<ModeChange>& modes) {
  const std::string time = Seconds(snapshot.time_ns);
  std::string json = "{\"time_s\":" + (snapshot.time_ns < 0 ? "null" : time);
  json += ",\"robots\":" + Array(snapshot.poses, [&](const run_formats::LivePose& pose) {
            return "[" + time + "," + Number(pose.x_m) + "," + Number(pose.y_m) + "," +
                   Number(pose.z_m) + "," + Number(pose.speed_m_s) + "]";
          });
  json += ",\"trails\":" + Array(snapshot.trails, [](const std::vector<TrailPoint>& trail) {
            return Array(trail, [](const TrailPoint& p) {
              return "[" + Seconds(p.time_ns) + "," + Number(p.x_m) + "," + Number(p.y_m) + "]";
            });
          });
  json += ",\"link_second\":" + std::to_string(snapshot.link_second);
  json += ",\"links\":" + Array(snapshot.links, [](const run_formats::LinkRow& row) {
            const double ratio = row.frames > 0 ? static_cast<double>(row.delivered) /
                                                      static_cast<double>(row.frames)
                                                : -1;
            return LinkArray(row.second, row.from, row.to, row.frames, row.delivered, ratio,
                             row.main_cause, row.main_cause_frames);
          });
  json += ",\"components_time_s\":" +
          (snapshot.components_time_ns < 0 ? "null" : Seconds(snapshot.components_time_ns));
  json += "," + TimelineMembers(snapshot.connectivity, snapshot.timing);
  json += ",\"skipped_updates\":" + std::to_string(snapshot.skipped_updates);
  json += ",\"modes\":" + ModeChangesArray(modes);
  std::vector<GcsVehicle> vehicles;
  for (const run_formats::LiveVehicle& vehicle : snapshot.vehicles)
    vehicles.push_back(GcsVehicleOf(vehicle));
  json += ",\"gcs_time_s\":" +
          (snapshot.vehicles_time_ns < 0 ? "null" : Seconds(snapshot.vehicles_time_ns));
  json += ",\"gcs\":" + GcsVehiclesArray(vehicles);
  return json + "}";
}

}  // namespace sitlnet::view

#include "view/replay_json.h"

#include <algorithm>
#include <cmath>

#include "run_formats/run_formats.h"
#include "view/gcs_vehicles.h"
#include "view/json_text.h"

namespace sitlnet::view {
namespace {

// The robot's autopilot interface, as its scenario declares it: "px4", "ardupilot" or null.
std::string AutopilotOf(const RobotPlan& robot) {
  if (robot.spec.px4_sim_port() > 0) return "\"px4\"";
  if (robot.spec.ardupilot_json_port() > 0) return "\"ardupilot\"";
  return "null";
}

}  // namespace

std::string RunJson(const Scenario& scenario, const std::string& run_dir, TimeNs end_ns,
                    bool live) {
  std::string json = "{\"name\":" + Quote(scenario.name);
  json += ",\"run_dir\":" + Quote(run_dir);
  json += ",\"live\":" + std::string(live ? "true" : "false");
  json += ",\"end_s\":" + Seconds(end_ns);
  json += ",\"robots\":" + Array(scenario.robots, [](const RobotPlan& robot) {
            return "{\"index\":" + std::to_string(robot.index) + ",\"name\":" + Quote(robot.name) +
                   ",\"autopilot\":" + AutopilotOf(robot) + "}";
          });
  std::vector<const proto::Obstacle*> obstacles;
  for (const proto::Obstacle& obstacle : scenario.spec.obstacle()) obstacles.push_back(&obstacle);
  json += ",\"obstacles\":" + Array(obstacles, [](const proto::Obstacle* box) {
            return "{\"name\":" + Quote(box->name()) + ",\"center_m\":" + Vec3(box->center_m()) +
                   ",\"size_m\":" + Vec3(box->size_m()) + ",\"yaw_deg\":" +
                   Number(box->yaw_deg()) + "}";
          });
  std::vector<std::string> columns;
  for (const char* c = run_formats::kLossHeader; *c != '\0'; ++c) {
    if (columns.empty() || *c == ',') columns.emplace_back();
    if (*c != ',') columns.back() += *c;
  }
  json += ",\"loss_columns\":" + Array(columns, Quote);
  return json + "}";
}

std::string RunJson(const ReplayedRun& record) {
  TimeNs end_ns = 0;
  for (const PoseSample& pose : record.poses) end_ns = std::max(end_ns, pose.time_ns);
  return RunJson(record.scenario, record.run_dir, end_ns, false);
}

std::string ModesJson(const ReplayedRun& record) {
  return "{\"modes\":" + ModeChangesArray(record.modes) + "}";
}

std::string GcsJson(const ReplayedRun& record) {
  std::vector<std::string> names;
  for (const RobotPlan& robot : record.scenario.robots) names.push_back(robot.name);
  return "{\"vehicles\":" + GcsVehiclesArray(GcsVehiclesOfSummary(record.summary_json, names)) +
         "}";
}

std::string TrajectoriesJson(const ReplayedRun& record) {
  std::vector<std::string> per_robot(record.scenario.robots.size());
  for (const PoseSample& pose : record.poses) {
    std::string& samples = per_robot[pose.robot];
    const double speed = std::sqrt(pose.vx_m_s * pose.vx_m_s + pose.vy_m_s * pose.vy_m_s +
                                   pose.vz_m_s * pose.vz_m_s);
    samples += (samples.empty() ? "[" : ",[") + Seconds(pose.time_ns) + "," + Number(pose.x_m) +
               "," + Number(pose.y_m) + "," + Number(pose.z_m) + "," + Number(speed) + "]";
  }
  return "{\"robots\":" +
         Array(per_robot, [](const std::string& samples) { return "[" + samples + "]"; }) + "}";
}

std::string LinksJson(const ReplayedRun& record) {
  return "{\"links\":" + Array(record.links, [](const LinkSecond& link) {
           return LinkArray(link.second, link.from, link.to, link.frames, link.delivered,
                            link.delivery_ratio, link.main_cause, link.main_cause_frames);
         }) + "}";
}

std::string TimelineJson(const ReplayedRun& record) {
  return "{" + TimelineMembers(record.connectivity, record.timing) + "}";
}

std::string FramesJson(const ReplayedRun& record, int from, int station, TimeNs end_ns,
                       TimeNs window_ns) {
  std::vector<const LossRow*> rows;
  const auto link = record.losses_by_link.find({from, station});
  if (link != record.losses_by_link.end()) {
    for (const size_t index : link->second) {
      const LossRow& row = record.losses[index];
      if (row.time_ns >= end_ns - window_ns && row.time_ns < end_ns) rows.push_back(&row);
    }
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const LossRow* a, const LossRow* b) { return a->time_ns < b->time_ns; });
  const size_t total = rows.size();
  if (rows.size() > kMaxFrameRows) rows.resize(kMaxFrameRows);
  std::string json = "{\"from\":" + std::to_string(from) + ",\"station\":" +
                     std::to_string(station) + ",\"start_ns\":" +
                     std::to_string(end_ns - window_ns) + ",\"end_ns\":" +
                     std::to_string(end_ns) + ",\"total\":" + std::to_string(total);
  json += ",\"rows\":" + Array(rows, [](const LossRow* row) { return Array(row->cells, Quote); });
  return json + "}";
}

}  // namespace sitlnet::view

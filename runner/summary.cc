#include "runner/summary.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include "run_formats/run_formats.h"
#include "runner/gcs_relay_stage.h"
#include "runner/run_folder.h"
#include "runner/run_record.h"

namespace sitlnet::runner {
namespace {

std::string Quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string Seconds(TimeNs ns) { return std::to_string(static_cast<double>(ns) / kNsPerS); }

// Split statistics of the communication graph.
std::string ConnectivityJson(const std::vector<run_formats::ConnectivitySample>& samples) {
  int max_components = samples.empty() ? 0 : 1;
  TimeNs split_ns = 0, first_split = -1, last_merge = -1;
  int previous = 1;
  for (const run_formats::ConnectivitySample& s : samples) {
    max_components = std::max(max_components, s.components);
    if (s.components > 1) {
      split_ns += kConnectivitySampleNs;
      if (first_split < 0) first_split = s.time_ns;
    } else if (previous > 1) {
      last_merge = s.time_ns;
    }
    previous = s.components;
  }
  return "{\"window_s\":" + Seconds(kConnectivityWindowNs) +
         ",\"max_components\":" + std::to_string(max_components) +
         ",\"time_split_s\":" + Seconds(split_ns) +
         ",\"first_split_s\":" + (first_split < 0 ? "null" : Seconds(first_split)) +
         ",\"last_merge_s\":" + (last_merge < 0 ? "null" : Seconds(last_merge)) +
         ",\"final_components\":" +
         std::to_string(samples.empty() ? 0 : samples.back().components) + "}";
}

// The closest approach of two robots, or null with fewer than two.
std::string SeparationJson(const Scenario& scenario,
                           const std::optional<run_formats::ClosestApproach>& closest) {
  if (!closest) return "null";
  return "{\"min_m\":" + std::to_string(closest->distance_m) +
         ",\"at_s\":" + Seconds(closest->time_ns) + ",\"robots\":[" +
         Quote(scenario.robots[closest->robot_a].name) + "," +
         Quote(scenario.robots[closest->robot_b].name) + "]}";
}

// DATA frames at the station they are for, by link class; null when no loss log was kept.
std::string DeliveryJson(const run_formats::LossLog* losses) {
  if (losses == nullptr) return "null";
  const auto counts = [](const run_formats::DeliveryCounts& c) {
    std::string ratio = "null";
    if (c.frames > 0) {
      ratio = std::to_string(static_cast<double>(c.delivered) / static_cast<double>(c.frames));
    }
    return "{\"frames\":" + std::to_string(c.frames) +
           ",\"delivered\":" + std::to_string(c.delivered) + ",\"ratio\":" + ratio + "}";
  };
  const run_formats::DeliveryByLinkClass& by_class = losses->delivery_by_link_class();
  return "{\"line_of_sight\":" + counts(by_class.line_of_sight) +
         ",\"obstructed\":" + counts(by_class.obstructed) + "}";
}

// What the GCS heard of each vehicle: a JSON array by system id, each with the address it sent
// from and the robot that has that address (null: none).
std::string VehiclesJson(const Scenario& scenario,
                         const std::vector<gcs::VehicleCounters>& vehicles) {
  std::string json = "[";
  for (const gcs::VehicleCounters& v : vehicles) {
    const int robot = RobotOfAddress(scenario, v.address);
    json += (json.size() > 1 ? ",{" : "{") + std::string("\"system_id\":") +
            std::to_string(v.system_id) + ",\"address\":" + Quote(FormatIpv4(v.address)) +
            ",\"robot\":" + (robot < 0 ? "null" : Quote(scenario.robots[robot].name)) +
            ",\"messages\":" + std::to_string(v.messages) +
            ",\"sequence_gaps\":" + std::to_string(v.sequence_gaps) + ",\"heartbeat\":";
    if (!v.heartbeat_seen) {
      json += "null}";
      continue;
    }
    json += "{\"type\":" + std::to_string(v.type) +
            ",\"autopilot\":" + std::to_string(v.autopilot) +
            ",\"base_mode\":" + std::to_string(v.base_mode) +
            ",\"custom_mode\":" + std::to_string(v.custom_mode) +
            ",\"armed\":" + (v.armed ? "true" : "false") + "}}";
  }
  return json + "]";
}

// The GCS relay's endpoints and counters; "null" without a relay.
std::string GcsRelayJson(const Scenario& scenario, const RunReport& report) {
  if (!report.gcs_relay) return "null";
  const gcs::GcsRelayCounters& c = report.gcs_relay->counters;
  const auto field = [](const char* name, uint64_t value) {
    return ",\"" + std::string(name) + "\":" + std::to_string(value);
  };
  return "{\"endpoints\":" + Quote(report.gcs_relay->endpoints) +
         field("from_vehicles", c.from_vehicles) + field("vehicle_addresses", c.vehicle_addresses) +
         field("to_gcs", c.to_gcs) + field("to_gcs_unreceived", c.to_gcs_unreceived) +
         field("from_gcs", c.from_gcs) + field("from_gcs_without_frame", c.from_gcs_without_frame) +
         field("from_gcs_bytes_dropped", c.from_gcs_bytes_dropped) +
         field("to_vehicles", c.to_vehicles) + field("to_vehicles_routed", c.to_vehicles_routed) +
         field("to_vehicles_failed", c.to_vehicles_failed) + field("gcs_clients", c.gcs_clients) +
         field("tlog_frames", c.tlog_frames) + field("tlog_bytes_skipped", c.tlog_bytes_skipped) +
         ",\"vehicles\":" + VehiclesJson(scenario, c.vehicles) + "}";
}

// The robot's physics counters; "null" when its physics ran on a node host (issue 35).
std::string PhysicsJson(const physics::PhysicsServer* physics, int index) {
  if (physics == nullptr) return "null";
  const physics::RobotCounters& phys = physics->counters(index);
  std::string json = "{\"commands_accepted\":" + std::to_string(phys.commands_accepted) +
                     ",\"states_sent\":" + std::to_string(phys.states_sent) + ",\"dropped\":" +
                     std::to_string(phys.dropped_malformed + phys.dropped_invalid +
                                    phys.dropped_wrong_robot + phys.dropped_foreign_source) +
                     ",\"failsafe_cuts\":" + std::to_string(phys.failsafe_cuts) +
                     ",\"json_frames\":" + std::to_string(phys.json_frames) +
                     ",\"json_resends\":" + std::to_string(phys.json_resends) +
                     ",\"json_restarts\":" + std::to_string(phys.json_restarts) +
                     ",\"json_missed_frames\":" + std::to_string(phys.json_missed_frames) +
                     ",\"json_dropped\":" + std::to_string(phys.json_dropped) +
                     ",\"json_clock_jumps\":" + std::to_string(phys.json_clock_jumps) + ",\"px4\":";
  if (const std::optional<physics::Px4Counters> px4 = physics->px4_counters(index)) {
    json += "{\"connections\":" + std::to_string(px4->connections) +
            ",\"sensors_sent\":" + std::to_string(px4->sensors_sent) +
            ",\"gps_sent\":" + std::to_string(px4->gps_sent) +
            ",\"actuator_controls\":" + std::to_string(px4->actuator_controls) +
            ",\"heartbeats_received\":" + std::to_string(px4->heartbeats_received) +
            ",\"ignored\":" + std::to_string(px4->ignored) +
            ",\"dropped\":" + std::to_string(px4->dropped) +
            ",\"bytes_skipped\":" + std::to_string(px4->bytes_skipped) +
            ",\"send_errors\":" + std::to_string(px4->send_errors) + "}";
  } else {
    json += "null";
  }
  return json + "}";
}

// The robot's autopilot rate in wall time; null without an autopilot that answered, or when its
// physics ran on a node host.
std::optional<physics::AutopilotRate> AutopilotRateOf(const physics::PhysicsServer* physics,
                                                      int index) {
  if (physics == nullptr || !physics->world().simulates(index)) return std::nullopt;
  const physics::AutopilotRate rate = physics->autopilot_rate(index);
  if (rate.nominal_hz <= 0) return std::nullopt;
  return rate;
}

std::string AutopilotRateJson(const std::optional<physics::AutopilotRate>& rate) {
  if (!rate) return "null";
  char text[200];
  std::snprintf(text, sizeof text,
                "{\"answers\":%llu,\"nominal_hz\":%.6g,\"achieved_hz\":%.6g,\"ratio\":%.6g}",
                static_cast<unsigned long long>(rate->answers), rate->nominal_hz,
                rate->AchievedHz(), rate->Ratio());
  return text;
}

// Over every autopilot: how many, the slowest (its ratio, its robot) and the median ratio; null
// without one.
std::string AutopilotRatesJson(const Scenario& scenario,
                               const physics::PhysicsServer* physics) {
  std::vector<std::pair<double, int>> ratios;  // (ratio, robot)
  for (int i = 0; i < static_cast<int>(scenario.robots.size()); ++i) {
    if (const auto rate = AutopilotRateOf(physics, i)) ratios.push_back({rate->Ratio(), i});
  }
  if (ratios.empty()) return "null";
  std::sort(ratios.begin(), ratios.end());
  const size_t n = ratios.size();
  const double median = n % 2 ? ratios[n / 2].first
                              : (ratios[n / 2 - 1].first + ratios[n / 2].first) / 2;
  char text[96];
  std::snprintf(text, sizeof text, "{\"autopilots\":%zu,\"min_ratio\":%.6g,\"median_ratio\":%.6g", n,
                ratios.front().first, median);
  return text + std::string(",\"slowest\":") + Quote(scenario.robots[ratios.front().second].name) +
         "}";
}

std::string RobotJson(const RobotSlot& robot, int index, tapbridge::BridgeCore& bridge,
                      const physics::PhysicsServer* physics) {
  const tapbridge::MediumCounters medium = bridge.medium_counters(index);
  const tapbridge::PortCounters& port = bridge.port_counters(index);
  std::string lost = "{";
  for (const auto& [reason, count] : medium.lost) {
    lost += (lost.size() > 1 ? "," : "") + Quote(reason) + ":" + std::to_string(count);
  }
  lost += "}";
  // Model details (sent_ok, retries, ...): with them sent = sent_ok + lost.retry_limit +
  // queue_drops + frames still queued (tests/integration/soak.sh checks it).
  std::string other = "{";
  for (const auto& [name, count] : medium.other) {
    other += (other.size() > 1 ? "," : "") + Quote(name) + ":" + std::to_string(count);
  }
  other += "}";
  std::string json = "{\"name\":" + Quote(robot.name);
  json += ",\"exit_status\":" +
          (robot.exit_status ? std::to_string(*robot.exit_status) : std::string("null"));
  json += ",\"log\":" + (robot.process ? Quote(robot.process->log_path()) : "null");
  // What its cgroup measured of every process it ran (null without one; docs/run.md).
  json += ",\"cgroup\":";
  if (robot.usage) {
    const auto measured = [](int64_t value, double unit) {
      return value < 0 ? std::string("null") : std::to_string(static_cast<double>(value) / unit);
    };
    json += "{\"cpu_s\":" + measured(robot.usage->cpu_ns, 1e9) +
            ",\"memory_peak_mib\":" + measured(robot.usage->memory_peak_bytes, 1 << 20) + "}";
  } else {
    json += "null";
  }
  json += ",\"medium\":{\"sent\":" + std::to_string(medium.sent) +
          ",\"delivered\":" + std::to_string(medium.delivered) +
          ",\"queue_drops\":" + std::to_string(medium.queue_drops) +
          ",\"queue_expired\":" + std::to_string(medium.queue_expired) + ",\"lost\":" + lost +
          ",\"other\":" + other + ",\"oversize_dropped\":" + std::to_string(port.oversize_dropped) +
          ",\"unknown_source_dropped\":" + std::to_string(port.unknown_source_dropped) + "}";
  json += ",\"physics\":" + PhysicsJson(physics, index);
  json += ",\"autopilot_rate\":" + AutopilotRateJson(AutopilotRateOf(physics, index)) + "}";
  return json;
}

// Each node link's round trips and bytes (a fleet's central), else null.
std::string FleetLinksJson(const RunReport& report) {
  if (report.fleet_links.empty()) return "null";
  std::string json = "[";
  for (const fleet::FleetLinkStats& node : report.fleet_links) {
    const coordinator::LinkStats& link = node.link;
    json += (json.size() > 1 ? ",{\"node\":" : "{\"node\":") + Quote(node.node) +
            ",\"round_trips\":" + std::to_string(link.round_trips) +
            ",\"round_trip_ns\":{\"p50\":" + std::to_string(link.round_trip_p50_ns) +
            ",\"p99\":" + std::to_string(link.round_trip_p99_ns) +
            ",\"max\":" + std::to_string(link.round_trip_max_ns) +
            "},\"bytes_up_per_iteration\":" + std::to_string(link.BytesUpPerRoundTrip()) +
            ",\"bytes_down_per_iteration\":" + std::to_string(link.BytesDownPerRoundTrip()) +
            ",\"bytes_up_total\":" + std::to_string(link.bytes_up) +
            ",\"bytes_down_total\":" + std::to_string(link.bytes_down) + "}";
  }
  return json + "]";
}

// Each node's lateness in realtime (a fleet's central), else null.
std::string FleetRealtimeJson(const RunReport& report) {
  if (report.fleet_realtime.empty()) return "null";
  const auto lateness = [](const tapbridge::LatenessStats& stats) {
    char text[160];
    std::snprintf(
        text, sizeof text, "{\"count\":%llu,\"p50_ms\":%.3f,\"p99_ms\":%.3f,\"max_ms\":%.3f}",
        static_cast<unsigned long long>(stats.count), static_cast<double>(stats.p50_ns) / kNsPerMs,
        static_cast<double>(stats.p99_ns) / kNsPerMs, static_cast<double>(stats.max_ns) / kNsPerMs);
    return std::string(text);
  };
  std::string json = "[";
  for (const RunReport::NodeLateness& node : report.fleet_realtime) {
    json += (json.size() > 1 ? ",{\"node\":" : "{\"node\":") + Quote(node.node) +
            ",\"late_entries\":" + lateness(node.late_entries) +
            ",\"late_writes\":" + lateness(node.late_writes) + "}";
  }
  return json + "]";
}

}  // namespace

void WriteSummaryAndPlots(const Scenario& scenario, const RunReport& report,
                          const coordinator::MetricsSummary& metrics, int64_t iterations_done,
                          const std::vector<RobotSlot>& robots, tapbridge::BridgeCore& bridge,
                          const physics::PhysicsServer* physics, MediumRecords& records,
                          const std::optional<run_formats::ClosestApproach>& closest,
                          const std::string& failure) {
  const std::string& dir = report.run_dir;
  const int robot_count = static_cast<int>(scenario.robots.size());
  const TimeNs simulated_ns = iterations_done * scenario.iteration_ns;
  const auto samples = records.connectivity().Finish(simulated_ns);
  run_formats::WriteConnectivityCsv(dir + "/connectivity.csv", samples, robot_count);

  std::vector<std::string> warnings;
  const std::vector<std::string> plots =
      run_formats::DrawPlots(dir, scenario, scenario.name, &warnings);
  for (const std::string& warning : warnings) {
    std::fprintf(stderr, "sitlnet run: warning: %s\n", warning.c_str());
  }

  // Every output is complete by now (the robots reaped, the medium's files and the plots
  // written): their hashes go into the summary, the one file left out.
  // A file that cannot be read costs the record, never the summary.
  const TimeNs hash_begin_ns = MonotonicNowNs();
  std::string outputs = "{";
  try {
    for (const OutputHash& output : HashOutputs(dir, report.files_before)) {
      outputs += (outputs.size() > 1 ? "," : "") + Quote(output.path) + ":{\"sha256\":\"" +
                 output.sha256 + "\",\"bytes\":" + std::to_string(output.bytes) + "}";
    }
    outputs += "}";
  } catch (const Error& error) {
    std::fprintf(stderr, "sitlnet run: warning: no record of the outputs: %s\n", error.what());
    outputs = "null";
  }
  const TimeNs hash_ns = MonotonicNowNs() - hash_begin_ns;

  std::string json = "{\"scenario\":" + Quote(scenario.name);
  json += ",\"source\":" + Quote(scenario.source_path);
  json += ",\"pacing\":" + Quote(proto::Timing::Pacing_Name(scenario.spec.timing().pacing()));
  json += ",\"seed\":" + std::to_string(scenario.spec.timing().seed());
  json += ",\"sitlnet_version\":" + Quote(std::string(SitlnetVersion()));
  json += ",\"scenario_text\":" + Quote(EffectiveScenarioText(scenario));
  json += ",\"shadowing\":" + std::string(scenario.spec.radio().shadowing() ? "true" : "false");
  // Where the world's origin is on Earth (trajectories.csv's latitude and longitude).
  const proto::GeodeticOrigin& origin = scenario.spec.geodetic_origin();
  char geodetic[160];
  std::snprintf(geodetic, sizeof geodetic,
                ",\"geodetic_origin\":{\"latitude_deg\":%.9g,\"longitude_deg\":%.9g,"
                "\"altitude_m\":%.9g}",
                origin.latitude_deg(), origin.longitude_deg(), origin.altitude_m());
  json += geodetic;
  json += ",\"duration_s\":" + Seconds(scenario.duration_ns);
  json += ",\"simulated_s\":" + Seconds(simulated_ns);
  json += ",\"interrupted\":" + std::string(report.interrupted ? "true" : "false");
  json += ",\"failure\":" + (failure.empty() ? std::string("null") : Quote(failure));
  json += ",\"metrics\":" + metrics.ToJson();
  json += ",\"autopilot_rates\":" + AutopilotRatesJson(scenario, physics);
  json += ",\"connectivity\":" + ConnectivityJson(samples);
  json += ",\"separation\":" + SeparationJson(scenario, closest);
  json += ",\"delivery\":" + DeliveryJson(records.losses());
  json += ",\"resources\":{\"startup_s\":" + Seconds(report.startup_ns) +
          ",\"loop_s\":" + Seconds(report.loop_ns) +
          ",\"stop_robots_s\":" + Seconds(report.stop_ns) +
          ",\"sitlnet_cpu_s\":" + std::to_string(report.self_cpu_s) +
          ",\"robots_cpu_s\":" + std::to_string(report.robots_cpu_s) +
          ",\"robot_max_rss_kib\":" + std::to_string(report.robot_max_rss_kib) +
          ",\"robot_median_rss_kib\":" + std::to_string(report.robot_median_rss_kib) +
          ",\"hash_outputs_s\":" + Seconds(hash_ns) + "}";
  json += ",\"medium_link\":";
  if (const auto& link = report.medium_link) {
    const network_side::MediumLinkStats::Means mean = link->PerRoundTrip();
    json += "{\"round_trips\":" + std::to_string(link->round_trips) +
            ",\"quiet_steps\":" + std::to_string(link->quiet_steps) +
            ",\"round_trip_us_mean\":" + std::to_string(mean.round_trip_us) +
            ",\"remote_medium_us_mean\":" + std::to_string(mean.remote_medium_us) +
            ",\"transport_us_mean\":" + std::to_string(mean.transport_us) +
            ",\"request_bytes_mean\":" + std::to_string(mean.request_bytes) +
            ",\"reply_bytes_mean\":" + std::to_string(mean.reply_bytes) + "}";
  } else {
    json += "null";
  }
  json += ",\"fleet_links\":" + FleetLinksJson(report);
  json += ",\"gcs_relay\":" + GcsRelayJson(scenario, report);
  json += ",\"fleet_realtime\":" + FleetRealtimeJson(report);
  json += ",\"robots\":[";
  for (int i = 0; i < robot_count; ++i) {
    json += (i ? "," : "") + RobotJson(robots[i], i, bridge, physics);
  }
  json += "],\"plots\":[";
  for (size_t i = 0; i < plots.size(); ++i) json += (i ? "," : "") + Quote(plots[i]);
  json += "],\"outputs\":" + outputs + "}\n";
  LineFile(dir + "/summary.json", "", 1, "summary").AppendRecord(json);

  std::fprintf(stderr, "sitlnet run: %s (%.1f s simulated, %s)\n", dir.c_str(),
               static_cast<double>(simulated_ns) / kNsPerS, metrics.ToText().c_str());
  for (const std::string& plot : plots) std::fprintf(stderr, "  %s\n", plot.c_str());
}

}  // namespace sitlnet::runner

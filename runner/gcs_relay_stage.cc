#include "runner/gcs_relay_stage.h"

#include <cstdio>

namespace sitlnet::runner {

std::vector<gcs::GcsEndpoint> GcsEndpointsOf(const std::vector<std::string>& texts) {
  if (texts.empty()) return {gcs::DefaultGcsEndpoint()};
  std::vector<gcs::GcsEndpoint> endpoints;
  for (const std::string& text : texts) {
    if (text == "none") {
      if (texts.size() > 1) throw Error("--gcs none: no other --gcs may be given with it");
      return {};
    }
    endpoints.push_back(gcs::ParseGcsEndpoint(text));
  }
  return endpoints;
}

const RobotPlan* RelayedGroundStation(const Scenario& scenario) {
  for (const RobotPlan& robot : scenario.robots) {
    if (robot.spec.ground_station() && robot.spec.image().empty()) return &robot;
  }
  return nullptr;
}

std::unique_ptr<gcs::GcsRelay> StartGcsRelay(const Scenario& scenario,
                                             const std::vector<gcs::GcsEndpoint>& endpoints,
                                             const std::string& run_dir,
                                             const std::string& program) {
  const RobotPlan* station = RelayedGroundStation(scenario);
  if (station == nullptr || endpoints.empty()) return nullptr;
  gcs::GcsRelayOptions options;
  options.station_netns = station->netns;
  options.endpoints = endpoints;
  options.tlog_path = run_dir + "/gcs.tlog";
  auto relay = std::make_unique<gcs::GcsRelay>(options);
  std::fprintf(stderr, "%s: ground station \"%s\": MAVLink on UDP %u relayed to %s\n",
               program.c_str(), station->name.c_str(), static_cast<unsigned>(options.station_port),
               relay->Describe().c_str());
  return relay;
}

std::optional<RunReport::GcsRelayReport> StopGcsRelay(gcs::GcsRelay* relay,
                                                      const std::string& program) {
  if (relay == nullptr) return std::nullopt;
  try {
    relay->Stop();
  } catch (const Error& error) {
    std::fprintf(stderr, "%s: %s\n", program.c_str(), error.what());
  }
  const RunReport::GcsRelayReport report{relay->Describe(), relay->counters()};
  const gcs::GcsRelayCounters& c = report.counters;
  std::fprintf(
      stderr,
      "%s: GCS relay: %llu datagrams from %llu vehicle addresses, %llu to %s "
      "(%llu not received), %llu from the GCS (%llu without a frame, dropped), %llu sent to "
      "vehicles (%llu failed), "
      "%llu frames in gcs.tlog\n",
      program.c_str(), static_cast<unsigned long long>(c.from_vehicles),
      static_cast<unsigned long long>(c.vehicle_addresses),
      static_cast<unsigned long long>(c.to_gcs), report.endpoints.c_str(),
      static_cast<unsigned long long>(c.to_gcs_unreceived),
      static_cast<unsigned long long>(c.from_gcs),
      static_cast<unsigned long long>(c.from_gcs_without_frame),
      static_cast<unsigned long long>(c.to_vehicles),
      static_cast<unsigned long long>(c.to_vehicles_failed),
      static_cast<unsigned long long>(c.tlog_frames));
  for (const gcs::VehicleCounters& v : c.vehicles) {
    const std::string heartbeat = !v.heartbeat_seen
                                      ? "no autopilot heartbeat"
                                      : std::string(v.armed ? "armed" : "disarmed") +
                                            ", custom mode " + std::to_string(v.custom_mode);
    std::fprintf(stderr, "%s: GCS relay: system %u: %llu messages, %llu missing by sequence, %s\n",
                 program.c_str(), static_cast<unsigned>(v.system_id),
                 static_cast<unsigned long long>(v.messages),
                 static_cast<unsigned long long>(v.sequence_gaps), heartbeat.c_str());
  }
  return report;
}

int RobotOfAddress(const Scenario& scenario, Ipv4 address) {
  for (size_t i = 0; i < scenario.robots.size(); ++i) {
    if (scenario.robots[i].wlan_address == address) return static_cast<int>(i);
  }
  return -1;
}

void GcsRelayLive::IterationEnded(const proto::coord::Start& start) {
  const TimeNs now_ns = MonotonicNowNs();
  if (now_ns < next_wall_ns_) return;
  next_wall_ns_ = now_ns + kPeriodNs;
  const gcs::GcsRelayCounters counters = relay_.counters();
  std::vector<run_formats::LiveVehicle> vehicles;
  vehicles.reserve(counters.vehicles.size());
  for (const gcs::VehicleCounters& v : counters.vehicles) {
    vehicles.push_back({RobotOfAddress(scenario_, v.address), v.system_id, v.messages,
                        v.sequence_gaps, v.heartbeat_seen, v.type, v.autopilot, v.base_mode,
                        v.custom_mode, v.armed});
  }
  live_.Vehicles(start.end_ns(), vehicles);
}

}  // namespace sitlnet::runner

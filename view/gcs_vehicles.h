// What the run's GCS relay heard of each vehicle (gcs_link/, docs/autopilots.md "Ground
// stations"), as the page shows it: the robot, its flight mode, armed or not, and the MAVLink
// loss the GCS saw. Live from the run (run_formats::LiveVehicle); replayed from summary.json's
// "gcs_relay", the counts at the run's end.
#ifndef SITLNET_VIEW_GCS_VEHICLES_H_
#define SITLNET_VIEW_GCS_VEHICLES_H_

#include <cstdint>
#include <string>
#include <vector>

#include "run_formats/run_formats.h"

namespace sitlnet::view {

struct GcsVehicle {
  int robot = -1;  // Robot index; -1: no robot of the scenario sent it.
  int system_id = 0;
  uint64_t messages = 0;
  uint64_t sequence_gaps = 0;
  bool heartbeat_seen = false;
  std::string mode;  // AutopilotModeName, or "custom mode N" for another autopilot; "" without
                     // a heartbeat.
  bool armed = false;
};

// `vehicle` with its mode named.
GcsVehicle GcsVehicleOf(const run_formats::LiveVehicle& vehicle);

// summary.json's gcs_relay.vehicles, each robot found by name in `robot_names` (index order).
// Empty when the run had no relay, or summary.json is not JSON or predates the field "robot".
std::vector<GcsVehicle> GcsVehiclesOfSummary(const std::string& summary_json,
                                             const std::vector<std::string>& robot_names);

// [{"robot": index or null, "system_id", "mode": text or null, "armed": bool or null,
//   "messages", "sequence_gaps", "loss": gaps / (messages + gaps) or null}, ...]
std::string GcsVehiclesArray(const std::vector<GcsVehicle>& vehicles);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_GCS_VEHICLES_H_

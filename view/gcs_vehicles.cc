#include "view/gcs_vehicles.h"

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>

#include "view/autopilot_mode.h"
#include "view/json_text.h"

namespace sitlnet::view {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

// The mode an autopilot's HEARTBEAT names; a number for an autopilot the tables do not know
// (sitlnet's test autopilot says MAV_AUTOPILOT_GENERIC).
std::string ModeName(uint8_t type, uint8_t autopilot, uint8_t base_mode, uint32_t custom_mode) {
  mavlink::Heartbeat heartbeat;
  heartbeat.type = type;
  heartbeat.autopilot = autopilot;
  heartbeat.base_mode = base_mode;
  heartbeat.custom_mode = custom_mode;
  const std::string name = AutopilotModeName(heartbeat);
  return name.empty() ? "custom mode " + std::to_string(custom_mode) : name;
}

const Value* Member(const Struct& object, const std::string& key) {
  const auto found = object.fields().find(key);
  return found == object.fields().end() ? nullptr : &found->second;
}

double NumberMember(const Struct& object, const std::string& key) {
  const Value* value = Member(object, key);
  return value != nullptr && value->kind_case() == Value::kNumberValue ? value->number_value() : 0;
}

GcsVehicle VehicleOfJson(const Struct& object, const std::vector<std::string>& robot_names) {
  GcsVehicle vehicle;
  vehicle.system_id = static_cast<int>(NumberMember(object, "system_id"));
  vehicle.messages = static_cast<uint64_t>(NumberMember(object, "messages"));
  vehicle.sequence_gaps = static_cast<uint64_t>(NumberMember(object, "sequence_gaps"));
  const Value* robot = Member(object, "robot");
  if (robot != nullptr && robot->kind_case() == Value::kStringValue) {
    const auto at = std::find(robot_names.begin(), robot_names.end(), robot->string_value());
    if (at != robot_names.end()) vehicle.robot = static_cast<int>(at - robot_names.begin());
  }
  const Value* heartbeat = Member(object, "heartbeat");
  if (heartbeat != nullptr && heartbeat->kind_case() == Value::kStructValue) {
    const Struct& h = heartbeat->struct_value();
    vehicle.heartbeat_seen = true;
    vehicle.mode = ModeName(static_cast<uint8_t>(NumberMember(h, "type")),
                            static_cast<uint8_t>(NumberMember(h, "autopilot")),
                            static_cast<uint8_t>(NumberMember(h, "base_mode")),
                            static_cast<uint32_t>(NumberMember(h, "custom_mode")));
    const Value* armed = Member(h, "armed");
    vehicle.armed =
        armed != nullptr && armed->kind_case() == Value::kBoolValue && armed->bool_value();
  }
  return vehicle;
}

}  // namespace

GcsVehicle GcsVehicleOf(const run_formats::LiveVehicle& v) {
  GcsVehicle vehicle;
  vehicle.robot = v.robot;
  vehicle.system_id = v.system_id;
  vehicle.messages = v.messages;
  vehicle.sequence_gaps = v.sequence_gaps;
  vehicle.heartbeat_seen = v.heartbeat_seen;
  if (v.heartbeat_seen) vehicle.mode = ModeName(v.type, v.autopilot, v.base_mode, v.custom_mode);
  vehicle.armed = v.armed;
  return vehicle;
}

std::vector<GcsVehicle> GcsVehiclesOfSummary(const std::string& summary_json,
                                             const std::vector<std::string>& robot_names) {
  Struct summary;
  if (!google::protobuf::util::JsonStringToMessage(summary_json, &summary).ok()) return {};
  const Value* relay = Member(summary, "gcs_relay");
  if (relay == nullptr || relay->kind_case() != Value::kStructValue) return {};
  const Value* vehicles = Member(relay->struct_value(), "vehicles");
  if (vehicles == nullptr || vehicles->kind_case() != Value::kListValue) return {};
  std::vector<GcsVehicle> out;
  for (const Value& vehicle : vehicles->list_value().values()) {
    if (vehicle.kind_case() == Value::kStructValue) {
      out.push_back(VehicleOfJson(vehicle.struct_value(), robot_names));
    }
  }
  return out;
}

std::string GcsVehiclesArray(const std::vector<GcsVehicle>& vehicles) {
  return Array(vehicles, [](const GcsVehicle& v) {
    const uint64_t expected = v.messages + v.sequence_gaps;
    return "{\"robot\":" + (v.robot < 0 ? std::string("null") : std::to_string(v.robot)) +
           ",\"system_id\":" + std::to_string(v.system_id) +
           ",\"mode\":" + (v.heartbeat_seen ? Quote(v.mode) : "null") +
           ",\"armed\":" + (v.heartbeat_seen ? (v.armed ? "true" : "false") : "null") +
           ",\"messages\":" + std::to_string(v.messages) +
           ",\"sequence_gaps\":" + std::to_string(v.sequence_gaps) + ",\"loss\":" +
           (expected == 0
                ? "null"
                : Number(static_cast<double>(v.sequence_gaps) / static_cast<double>(expected))) +
           "}";
  });
}

}  // namespace sitlnet::view

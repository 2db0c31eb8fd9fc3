// What a real autopilot's flight says in MAVLink, for the tests that fly one with a node-mavlink
// GCS script (autopilot_radio_test.cc, shipped_fleet_scenarios_test.cc): the messages that
// crossed the medium (medium.pcap, decoded by node-mavlink), the events the GCS printed, and the
// truth at an event's time.
#ifndef SITLNET_TESTS_INTEGRATION_MAVLINK_ORACLE_H_
#define SITLNET_TESTS_INTEGRATION_MAVLINK_ORACLE_H_

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {

// MAVLink messages that crossed the medium one way, as node-mavlink decoded them
// (tests/node_mavlink/decode.cjs, CRC and CRC_EXTRA checked).
struct Crossed {
  std::map<std::string, int> messages;  // message name -> count
  std::map<std::string, int> commands;  // COMMAND_LONG command id -> count
  std::map<std::pair<std::string, std::string>, int> commands_to;  // (target system, id) -> count
  std::map<std::string, int> systems;  // sender's MAVLink system id -> messages
  std::string counts;                  // "COUNTS valid=.. invalid=.. unknown=.."
  int Messages(const std::string& name) const;
  int Commands(int id) const;
  // COMMAND_LONGs of command `id` for MAVLink system `target`.
  int CommandsTo(int target, int id) const;
};

// `bytes` (MAVLink frames) decoded by node-mavlink; `file` holds them for node's stdin.
Crossed DecodeMavlink(const std::string& bytes, const std::string& file);

// The UDP payloads in OUT/medium.pcap that match the tshark display `filter` (first
// transmissions, no ICMP quoting them), by the value of the tshark field `key_field` (e.g.
// "ip.src") -> bytes. tshark dissects every frame (15 s for a run of four ArduCopters), so
// tcpdump first keeps only the frames that match the BPF filter `prefilter` (2 s), which must
// keep every frame `filter` matches.
std::map<std::string, std::string> UdpPayloads(const std::string& out, const std::string& prefilter,
                                               const std::string& filter,
                                               const std::string& key_field);

// An event a GCS script printed, with the autopilot's time (s): guided_flight_plan.cjs's
// "NAME t=S" or px4_flight_plan.cjs's "EVENT NAME t_ms=MS [since_ms=MS]" (since when the steady
// state the event ends held; the event's own time when there is none).
struct FlightEvent {
  double t_s = 0;
  double since_s = 0;
};
// The events of the lines of `log` that start with `prefix` (fleet_flight_plan.cjs: "sys=N ").
std::map<std::string, FlightEvent> FlightEvents(const std::string& log,
                                                const std::string& prefix = "");

// The row at or just before `t_s` (rows every 100 ms).
const TrajectoryRow& RowAt(const std::vector<TrajectoryRow>& rows, double t_s);

}  // namespace sitlnet::nns::testing

#endif  // SITLNET_TESTS_INTEGRATION_MAVLINK_ORACLE_H_

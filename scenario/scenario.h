// sitlnet scenario: parse a .textproto scenario file into a validated,
// immutable Scenario (MuJoCo's spec -> model step). Every module reads its
// configuration from here; field meanings and defaults are in docs/scenario.md.
#ifndef SITLNET_SCENARIO_SCENARIO_H_
#define SITLNET_SCENARIO_SCENARIO_H_

#include <google/protobuf/text_format.h>

#include <string>
#include <string_view>
#include <vector>

#include "clock/pacing.h"
#include "common/common.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet {

//------------------------------- Derived plan -------------------------------

// Per-robot facts derived from the scenario at load time.
struct RobotPlan {
  int index = 0;             // Position in the scenario's robot list, from 0.
  std::string name;          // As written in the scenario.
  std::string netns;         // "<scenario>-<robot>", an `ip netns` name.
  std::string root_veth;     // Root-namespace end of ctl0: "<scenario>-c<index>".
  MacAddress wlan_mac;       // RobotMac(index).
  Ipv4 wlan_address;         // On wlan0, inside the wlan subnet.
  Ipv4 ctl_root_address;     // Root side of the ctl0 point-to-point /30.
  Ipv4 ctl_robot_address;    // Robot side of the ctl0 /30 (ctl0 inside the robot).
  proto::Robot spec;         // The robot as written, defaults readable via accessors.
  proto::Airframe airframe;  // Resolved airframe (the named one or the default).
  int node = -1;             // Index in Scenario::nodes of the host that runs it; -1: no nodes.
};

// A node host of the scenario (issue 35) and the robots it runs.
struct NodePlan {
  std::string name;         // A DNS label, as written.
  std::vector<int> robots;  // Global robot indices, ascending.
};

// The names the plan gives a robot's namespace and its root-side veth (RobotPlan::netns,
// ::root_veth); nns checks its state file against them.
std::string RobotNetnsName(const std::string& scenario, const std::string& robot);
std::string RobotRootVethName(const std::string& scenario, int index);

// A validated scenario. Immutable after LoadScenario* returns.
struct Scenario {
  std::string source_path;  // File it came from ("<string>" for in-memory text).
  proto::Scenario spec;     // As parsed; proto2 accessors yield the defaults.
  std::string name;
  std::vector<RobotPlan> robots;
  Ipv4Prefix wlan_subnet;
  Ipv4Prefix ctl_subnet;
  TimeNs iteration_ns = 0;
  TimeNs physics_step_ns = 0;
  TimeNs network_step_ns = 0;
  TimeNs duration_ns = 0;
  int physics_steps_per_iteration = 0;  // N_phy
  int network_steps_per_iteration = 0;  // N_net
  std::vector<NodePlan> nodes;          // Empty: every robot runs on one host.

  // Index of the robot called `name`, or -1.
  int RobotIndex(std::string_view robot_name) const;
  // Index of the node called `name`, or -1.
  int NodeIndex(std::string_view node_name) const;
  // The robots of a slice (a node host's share, issue 35): `requested` if it is ascending
  // indices of this scenario's robots, every index if it is empty. Throws Error otherwise.
  std::vector<int> RobotSlice(const std::vector<int>& requested) const;
  // timing.pacing as the clock's type: the one place that reads the proto's enum.
  clock::Pacing pacing() const;
  // Paced in lockstep (as fast as the host allows), not against the wall clock.
  bool lockstep() const { return pacing() == clock::Pacing::kLockstep; }
};

//-------------------------------- Loading -----------------------------------

// Reads, parses and validates a scenario file. Throws Error whose message is
// one line "path:line:col: <what>: <rule>" (line and column from 1).
Scenario LoadScenarioFile(const std::string& path);

// Same for text already in memory; `source_name` prefixes error messages.
Scenario LoadScenarioText(std::string_view text, const std::string& source_name);

// Validates a spec edited in memory (the command line's overrides): the same rules, with
// messages that name `source_name` alone (an edited spec has no lines).
Scenario ValidateScenarioSpec(proto::Scenario spec, const std::string& source_name);

// The proto's spelling of `pacing`, for a spec edited in memory.
proto::Timing::Pacing ProtoPacing(clock::Pacing pacing);

// Longest scenario name: the root-side veth "<name>-c<index>" must fit the
// kernel's 15-character interface names with up to 1000 robots.
inline constexpr int kMaxScenarioNameLength = 10;
inline constexpr int kMaxRobots = 1000;
inline constexpr int kMaxRobotNameLength = 32;
inline constexpr int kMaxNodeNameLength = 63;    // A DNS label (RFC 1035 2.3.4)
inline constexpr double kMaxRos2ClockHz = 1000;  // Timing.ros2_clock_hz
// Largest duration_ms: a year of virtual time keeps every derived nanosecond count (and sums of
// them) far from int64's end; nothing a scenario needs comes near it.
inline constexpr int64_t kMaxDurationMs = 366LL * 24 * 3600 * 1000;

// Parses protobuf text format into `message` (also used for image manifests).
// Throws Error "source:line:col: <protobuf's message>" on the first error.
// `locations` (may be null) receives field locations for later messages.
void ParseTextProtoOrThrow(std::string_view text, const std::string& source_name,
                           google::protobuf::Message* message,
                           google::protobuf::TextFormat::ParseInfoTree* locations = nullptr);

// Reads a whole file; throws Error "open <what> "path": <reason>".
std::string ReadFileOrThrow(const std::string& path, const std::string& what);

//------------------------- Checks against the host --------------------------

// An IPv4 route of the root namespace, as nns reads it with libnl.
struct HostRoute {
  Ipv4Prefix destination;
  std::string device;
};

// Throws Error naming the scenario subnet and the host route it overlaps.
// Default routes (0.0.0.0/0) do not count: they shadow nothing.
void CheckAddressPlanAgainstRoutes(const Scenario& scenario,
                                   const std::vector<HostRoute>& host_routes);

}  // namespace sitlnet

#endif  // SITLNET_SCENARIO_SCENARIO_H_

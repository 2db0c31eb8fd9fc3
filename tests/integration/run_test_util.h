// Helpers of the `sitlnet run` integration tests (run_test.cc, autopilot_run_test.cc): scenarios
// on subnets of their own, a run, what a run must leave behind, and the capture's frames.
#ifndef SITLNET_TESTS_INTEGRATION_RUN_TEST_UTIL_H_
#define SITLNET_TESTS_INTEGRATION_RUN_TEST_UTIL_H_

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {

// A scenario named "ru<pid%10000><slot>" on subnets of its own (wlan 10.<240+slot>.<pid%250>.0/24,
// ctl 10.<220+slot>.<pid%250>.0/24); `robots` is the robot blocks' text, `extra` more top-level
// fields, `address_fields` more fields of the addresses block (e.g. "ipv6: IPV6_LINK_LOCAL").
struct RunScenario {
  std::string name;
  std::string path;
};
RunScenario WriteScenario(int slot, const std::string& robots, const std::string& extra = "",
                          const std::string& address_fields = "");
// The first three octets of a slot's wlan subnet, with the trailing dot: "10.252.17.".
std::string WlanPrefix(int slot);

// Robot blocks for WriteScenario: a ground station "gcs" at index 0 (no image: `sitlnet run`
// relays its MAVLink to the host) and two of sitlnet's test autopilots sending it their telemetry,
// "ap" on ArduPilot's JSON protocol and "px" on PX4's (system ids 2 and 3).
std::string RelayFleetRobots(int slot);

// `sitlnet run SCENARIO --out OUT --no-progress EXTRA...`, 300 s at most.
CommandResult SitlnetRun(const RunScenario& scenario, const std::string& out,
                         std::vector<std::string> extra_args);

// A number of summary.json after `key` ("\"stf\":{\"mean\":"), within the text after `after`;
// NaN if absent.
double SummaryNumber(const std::string& summary, const std::string& after, const std::string& key);

// `sitlnet run SCENARIO --out OUT --no-progress`, stopped with SIGINT (in order, its outputs
// complete) once `done()` holds, checked when a file under OUT/robots changes (a GCS robot's
// log) and at least every 200 ms, or after `timeout_ns`; the run may also end by itself. For a
// flight that ends at a virtual instant nobody knows beforehand: its scenario's duration is a
// generous cap. exit_code: 130 if stopped, 0 if it ended by itself.
CommandResult SitlnetRunUntil(const RunScenario& scenario, const std::string& out,
                              const std::function<bool()>& done, TimeNs timeout_ns);

// No state, no namespace of robots "a" and "b", no ctl link of the scenario is left.
void ExpectNothingLeft(const std::string& name);

// On-air times (s) of first transmissions (no MAC retries) in OUT/medium.pcap matching the
// tshark display `filter`; with their UDP lengths and IPv6 sources if asked.
std::vector<double> CapturedTimes(const std::string& out, const std::string& filter,
                                  std::vector<int>* udp_lengths = nullptr,
                                  std::vector<std::string>* sources = nullptr);

// One row of a run's trajectories.csv: time and world ENU position.
// Two flockers 6 m apart flying towards x = 40 m (RunTest, VerifyTest).
inline constexpr char kTwoFlockers[] =
    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"flocker\" "
    "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
    "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"flocker\" "
    "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n";

struct TrajectoryRow {
  double t_s = 0;
  double x_m = 0, y_m = 0, z_m = 0;
};
// The rows of robot index `robot` in the text of a trajectories.csv (every 100 ms from 0).
std::vector<TrajectoryRow> TrajectoryRows(const std::string& csv, int robot);

// A GCS on the host, as docs/howto-autopilot-fleet.md (step 4) has one: `script` of
// tests/node_mavlink run by node with `args`, which make it bind a free UDP port and print
// "LISTENING on UDP port N"; its output goes to the file `output`. `sitlnet run --gcs
// udp:127.0.0.1:N` (gcs_flag()) joins the ground station to it. Killed with this object unless it
// exited first.
class HostGcs {
 public:
  HostGcs(const std::string& script, const std::vector<std::string>& args,
          const std::string& output);
  // The GCS bound its port within 30 s.
  bool started() const { return port_ != 0; }
  // "udp:127.0.0.1:N", the value of the run's --gcs.
  std::string gcs_flag() const { return "udp:127.0.0.1:" + std::to_string(port_); }
  integration_test::Child& gcs() { return *gcs_; }

 private:
  std::optional<integration_test::Child> gcs_;
  int port_ = 0;
};

// Skips the test when `why_missing` (a ...Missing() above or below) is not empty, saying why; under
// CI=true fails it instead.
#define SITLNET_REQUIRE(why_missing)                                   \
  do {                                                                 \
    if (const std::string missing = (why_missing); !missing.empty()) { \
      if (::sitlnet::integration_test::IsCi()) FAIL() << missing;      \
      GTEST_SKIP() << missing;                                         \
    }                                                                  \
  } while (0)

// Skips (fails under CI=true) when root, the autopilot of `why_missing` or node-mavlink is
// missing: what flying a real autopilot with a node-mavlink GCS needs.
#define SITLNET_REQUIRE_FLIGHT(why_missing)                         \
  do {                                                              \
    SITLNET_REQUIRE_NNS_PRIVILEGES();                               \
    SITLNET_REQUIRE(why_missing);                                   \
    SITLNET_REQUIRE(::sitlnet::nns::testing::NodeMavlinkMissing()); \
  } while (0)

// A port of 127.0.0.1 free now (bound and released; `type` SOCK_DGRAM or SOCK_STREAM), for a GCS
// that starts later or a relay that listens there; 0 if none could be had.
int FreePort(int type);

// tests/node_mavlink/host_gcs.cjs with `args` (PORT SECONDS [JUNK]) in `gcs`, bound: its UDP
// port, or 0 if it did not bind within 30 s.
int StartHostGcs(std::optional<integration_test::Child>* gcs, const std::vector<std::string>& args);

// The wall_ms of the first HEARTBEAT ("HEARD sysid=S msgid=0 ... wall_ms=W") of each system id
// in host_gcs.cjs's output: ms from binding its port to hearing it.
std::map<int, int> FirstHeartbeatMs(const std::string& gcs_output);

// The same in the vehicles' clock, for vehicles that share one (a lockstep run's autopilots): ms
// from the first time_boot_ms the GCS heard (" boot_ms=T") to the latest one heard before each
// system's first HEARTBEAT. Both are at most one message late, so this may be short by the gap
// between two messages; it does not depend on how fast the host runs the clock.
std::map<int, int> FirstHeartbeatClockMs(const std::string& gcs_output);

// A lockstep ground station's robot image (tests/node_mavlink/lockstep_station.cjs): `script` of
// tests/node_mavlink with `args`, run by node, the folder bound in; ready once bound. Returns the
// manifest's path.
std::string WriteStationImage(const std::string& script, const std::vector<std::string>& args);

// tests/node_mavlink: node-mavlink scripts (scripts/setup installs the package there).
std::string NodeMavlinkDir();
// Why SITLNET_ARDUPILOT_DIR names no ArduCopter build (and how to make one), or "" if it does.
std::string ArduPilotMissing();
// Why SITLNET_PX4_DIR names no PX4 build (and how to make one), or "" if it does. Flying it
// also needs NodeMavlinkMissing() empty.
std::string Px4Missing();
// Why node-mavlink cannot run here, or "" if it can.
std::string NodeMavlinkMissing();
// The flight tests' autopilots in the manifests' lean profile (docs/autopilots.md, "The lean
// profile"): true when SITLNET_TEST_AUTOPILOT_PROFILE is "lean". Every real autopilot of
// px4_flight_test, arducopter_flight_test and autopilot_fleet_test then gets `--lean`.
bool LeanAutopilots();

}  // namespace sitlnet::nns::testing

#endif  // SITLNET_TESTS_INTEGRATION_RUN_TEST_UTIL_H_

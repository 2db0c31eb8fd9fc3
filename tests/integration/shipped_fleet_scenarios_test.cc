// The shipped fleet scenarios fly (issue 32: scenarios/px4_fleet.textproto and
// scenarios/ardupilot_fleet.textproto), as docs/howto-autopilot-fleet.md tells a user to fly
// them: the scenario file unchanged, only `--pacing lockstep --duration S` on the command line; a
// GCS on the host (tests/node_mavlink/fleet_gcs.cjs, node-mavlink) reaches the four vehicles only
// through the run's own relay of the ground station (`--gcs udp:127.0.0.1:PORT`, the how-to's step
// 4 on a port of the test's own). Each vehicle, told apart by its system id, arms, takes off to 5
// m, holds, lands and disarms. Oracles: the truth in trajectories.csv, the commands as they crossed
// the medium (medium.pcap, decoded by node-mavlink), and the relay's counters in summary.json.
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tests/integration/mavlink_oracle.h"
#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::Child;
using integration_test::ReadAll;
using integration_test::SitlnetBinary;
using integration_test::SourceDir;
using integration_test::TempDir;

constexpr int kVehicles = 4;  // robots 1..4 of both scenarios, system id = robot index
// The wlan0 addresses of the scenarios' default subnet (docs/scenario.md): host index + 1.
std::string WlanAddress(int robot) { return "10.77.0." + std::to_string(robot + 1); }

// The run's virtual duration at most: the test stops it once the GCS is done (every vehicle
// disarmed). The GCS acts on the wall clock, outside the lock-step, so when the vehicles disarm in
// virtual time depends on the host's speed.
constexpr const char* kDurationCapS = "150";

// The flight: 5 m up (as autopilot_radio_test.cc's), a hold, back to home, down.
constexpr double kAltitudeM = 5;
// ArduCopter's hold (s) at the altitude and at home: its steady window below starts 1 s after it
// reached the altitude and must hold more than 20 rows.
constexpr const char* kHoldS = "2";

// How one autopilot's flight plan names its events, and the bounds its flights are held to
// (autopilot_radio_test.cc's: the altitude within issue 31's 0.3 m while it holds).
struct Autopilot {
  const char* kind;      // fleet_gcs.cjs's VEHICLE kind
  const char* scenario;  // in scenarios/
  const char* name;      // the scenario's name
  // The steady hold at the altitude: from `hold_from`'s since (plus `hold_after_s`) to `hold_to`.
  const char* hold_from;
  double hold_after_s;
  const char* hold_to;
  int land_command;  // the COMMAND_LONG that lands it
  double landed_m;   // its height above where it armed when it disarmed, at most
};

// Vehicle `id`'s flight: its events in the GCS's output, the truth, the commands to it.
void ExpectVehicleFlew(const Autopilot& autopilot, int id, const std::string& gcs_log,
                       const std::string& out, const Crossed& commands) {
  const std::string who = std::string(autopilot.kind) + " sys=" + std::to_string(id);
  const std::map<std::string, FlightEvent> events =
      FlightEvents(gcs_log, "sys=" + std::to_string(id) + " ");
  bool all = true;
  for (const char* event : {"ARMED", autopilot.hold_from, autopilot.hold_to, "DISARMED"}) {
    EXPECT_EQ(events.count(event), 1u) << who << ": " << event;
    all = all && events.count(event) == 1;
  }
  if (!all) {
    // What the autopilot itself said (its estimator's and commander's lines): the GCS hears only
    // the status texts it chose to send.
    const std::string log = ReadAll(out + "/robots/uav" + std::to_string(id) + ".log");
    ADD_FAILURE() << who << "'s own log, last 6000 bytes:\n"
                  << log.substr(log.size() > 6000 ? log.size() - 6000 : 0);
    return;
  }
  const std::vector<TrajectoryRow> rows = TrajectoryRows(ReadAll(out + "/trajectories.csv"), id);
  ASSERT_FALSE(rows.empty()) << who;
  const TrajectoryRow& armed = RowAt(rows, events.at("ARMED").t_s);
  const double from_s = events.at(autopilot.hold_from).since_s + autopilot.hold_after_s;
  const double to_s = events.at(autopilot.hold_to).t_s;
  double altitude_error_m = 0;
  int rows_held = 0;
  for (const TrajectoryRow& row : rows) {
    if (row.t_s < from_s || row.t_s >= to_s) continue;
    altitude_error_m = std::max(altitude_error_m, std::fabs(row.z_m - armed.z_m - kAltitudeM));
    ++rows_held;
  }
  const double landed_m = RowAt(rows, events.at("DISARMED").t_s).z_m - armed.z_m;
  EXPECT_GT(rows_held, 20) << who;
  EXPECT_LT(altitude_error_m, 0.3) << who;
  EXPECT_LT(std::fabs(landed_m), autopilot.landed_m) << who;
  EXPECT_LT(std::fabs(rows.back().z_m - armed.z_m), autopilot.landed_m) << who << " at the end";
  // Its commands crossed the medium: arm, take off, land, each for its system id.
  EXPECT_GT(commands.CommandsTo(id, 400), 0) << who << ": COMPONENT_ARM_DISARM";
  EXPECT_GT(commands.CommandsTo(id, 22), 0) << who << ": NAV_TAKEOFF";
  EXPECT_GT(commands.CommandsTo(id, autopilot.land_command), 0) << who << ": land";
  std::printf(
      "[ measured ] %s: armed %.1f s, held %.1f-%.1f s within %.3f m of %.0f m, disarmed %.1f s "
      "(virtual) %.3f m above where it armed\n",
      who.c_str(), events.at("ARMED").t_s, from_s, to_s, altitude_error_m, kAltitudeM,
      events.at("DISARMED").t_s, landed_m);
}

void FlyShippedScenario(const Autopilot& autopilot) {
  const auto start = std::chrono::steady_clock::now();
  const std::string work = TempDir() + "/" + autopilot.name + "-shipped";
  ASSERT_EQ(RunCommand({"mkdir", "-p", work}).exit_code, 0);
  // The GCS on the host, on a free port; the run's relay sends to that port.
  const std::string gcs_output = work + "/gcs.out";
  std::vector<std::string> args = {"0", std::to_string(kAltitudeM), kHoldS, "0,0"};
  for (int id = 1; id <= kVehicles; ++id) {
    args.push_back(std::string(autopilot.kind) + ":" + std::to_string(id));
  }
  HostGcs host("fleet_gcs.cjs", args, gcs_output);
  ASSERT_TRUE(host.started()) << ReadAll(gcs_output);

  DownGuard guard(autopilot.name);
  const RunScenario scenario{autopilot.name, SourceDir() + "/scenarios/" + autopilot.scenario};
  const std::string out = work + "/out";
  const auto run_start = std::chrono::steady_clock::now();
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress", "--pacing",
             "lockstep", "--duration", kDurationCapS, "--gcs", host.gcs_flag()});
  // The GCS exits once every vehicle disarmed; then the run stops in order (exit 130).
  EXPECT_EQ(host.gcs().Wait(250 * kNsPerS), 0) << ReadAll(gcs_output).substr(0, 4000);
  kill(run.pid(), SIGINT);
  const int run_exit = run.Wait(60 * kNsPerS);
  const double run_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  EXPECT_TRUE(run_exit == 130 || run_exit == 0) << run_exit << " " << run.err();
  const std::string gcs_log = ReadAll(gcs_output);

  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_EQ(SummaryNumber(summary, "\"gcs_relay\":", "\"vehicle_addresses\":"), kVehicles)
      << summary;
  // What the relay sent each vehicle over the radio.
  std::map<std::string, std::string> sent = UdpPayloads(out, "udp and src host " + WlanAddress(0),
                                                        "ip.src == " + WlanAddress(0), "ip.dst");
  for (int id = 1; id <= kVehicles; ++id) {
    const Crossed commands =
        DecodeMavlink(sent[WlanAddress(id)], work + "/to" + std::to_string(id) + ".bin");
    EXPECT_NE(commands.counts.find(" invalid=0 "), std::string::npos) << commands.counts;
    ExpectVehicleFlew(autopilot, id, gcs_log, out, commands);
  }
  ExpectNothingLeft(autopilot.name);
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", work});
  std::printf("[ measured ] %s: the run %.1f s wall, the whole test %.1f s\n", autopilot.scenario,
              run_s,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// px4_flight_plan.cjs: HOLD ends 3 s of PX4's time steady at the altitude; LAND is sent once it
// arrived back at home. Landed as autopilot_radio_test.cc's PX4 flight.
TEST(ShippedFleetScenariosTest, EveryPx4OfThePx4FleetFliesFromAHostGcsThroughTheRelay) {
  SITLNET_REQUIRE_FLIGHT(Px4Missing());
  FlyShippedScenario({"px4", "px4_fleet.textproto", "px4fleet", "HOLD", 0, "HOLD", 21, 0.1});
}

// guided_flight_plan.cjs: from 1 s after TAKEOFF_REACHED (the altitude within 0.1 m) to LAND.
// DO_SET_MODE (176) asks for LAND. Landed as autopilot_radio_test.cc's ArduCopter flight.
TEST(ShippedFleetScenariosTest,
     EveryArduCopterOfTheArduPilotFleetFliesFromAHostGcsThroughTheRelay) {
  SITLNET_REQUIRE_FLIGHT(ArduPilotMissing());
  FlyShippedScenario({"arducopter", "ardupilot_fleet.textproto", "apfleet", "TAKEOFF_REACHED", 1,
                      "LAND", 176, 0.05});
}

// Issue 47, item 4, with the real autopilots: the shipped PX4 fleet, its GCS (node-mavlink)
// started 5 s after the run's relay and restarted once. Each instance hears every vehicle's
// HEARTBEAT within a second of the vehicles' clock after it began to hear them: PX4 sends one
// each second of its clock (100 ms slack, not derived). That clock is the run's (lockstep), so
// the bound holds however fast the host runs it; the wall time is printed. The first instance
// (host_gcs.cjs) only listens. The restarted one (fleet_gcs.cjs) arms and takes off vehicle
// kFlown alone; the run stops once it held the altitude (px4_flight_plan.cjs's HOLD). Oracles:
// trajectories.csv (it held the altitude, the others never left the ground) and medium.pcap
// (arm and take-off commands crossed the radio to it, to no other).
TEST(ShippedFleetScenariosTest,
     APx4FleetsGcsThatStartsLateAndRestartsHearsEveryVehicleAndFliesOne) {
  SITLNET_REQUIRE_FLIGHT(Px4Missing());
  constexpr int kFlown = 3;
  const int port = FreePort(SOCK_DGRAM);
  ASSERT_NE(port, 0);
  DownGuard guard("px4fleet");
  const std::string out = TempDir() + "/px4-late-gcs";
  Child run({SitlnetBinary(), "run", SourceDir() + "/scenarios/px4_fleet.textproto", "--out", out,
             "--no-progress", "--pacing", "lockstep", "--duration", kDurationCapS, "--gcs",
             "udp:127.0.0.1:" + std::to_string(port)});
  ASSERT_TRUE(run.WaitForOutput(true, "relayed to", 60 * kNsPerS)) << run.err();
  // The stimulus, not a synchronisation: the GCS starts 5 s (wall) after the relay.
  std::this_thread::sleep_for(std::chrono::seconds(5));
  std::optional<Child> first_gcs;
  ASSERT_EQ(StartHostGcs(&first_gcs, {std::to_string(port), "3"}), port) << first_gcs->err();
  ASSERT_EQ(first_gcs->Wait(30 * kNsPerS), 0) << first_gcs->err();
  // The restart: the same port, a GCS that flies one vehicle (5 m, to home and down).
  const std::string flown_output = out + "-fleet-gcs.out";
  HostGcs restarted("fleet_gcs.cjs",
                    {std::to_string(port), std::to_string(kAltitudeM), kHoldS, "0,0",
                     "px4:" + std::to_string(kFlown)},
                    flown_output);
  ASSERT_TRUE(restarted.started()) << ReadAll(flown_output);
  // The GCS acts on the wall clock: the run stops in order once the vehicle held the altitude.
  const std::string held = "sys=" + std::to_string(kFlown) + " EVENT HOLD";
  EXPECT_TRUE(integration_test::WaitForFiles(
      TempDir(), [&] { return ReadAll(flown_output).find(held) != std::string::npos; },
      200 * kNsPerS))
      << ReadAll(flown_output).substr(0, 4000);
  kill(run.pid(), SIGINT);
  const int run_exit = run.Wait(60 * kNsPerS);
  EXPECT_TRUE(run_exit == 130 || run_exit == 0) << run_exit << " " << run.err();
  kill(restarted.gcs().pid(), SIGTERM);
  restarted.gcs().Wait(10 * kNsPerS);
  const std::string flown_log = ReadAll(flown_output);
  const std::string outputs[] = {first_gcs->out(), flown_log};
  for (int instance = 1; instance <= 2; ++instance) {
    const std::map<int, int> clock = FirstHeartbeatClockMs(outputs[instance - 1]);
    const std::map<int, int> wall = FirstHeartbeatMs(outputs[instance - 1]);
    for (int id = 1; id <= kVehicles; ++id) {
      ASSERT_TRUE(clock.count(id) && wall.count(id))
          << "instance " << instance << ", system " << id << "\n"
          << outputs[instance - 1].substr(0, 2000);
      EXPECT_LE(clock.at(id), 1100) << "instance " << instance << ", system " << id;
      // The clock bound counts from the first message heard, so it cannot see a relay that
      // starts late; the wall clock from the bind can, coarsely (1.1-1.4 s seen at load 29-34,
      // when lockstep ran slower than real time).
      EXPECT_LE(wall.at(id), 3000) << "instance " << instance << ", system " << id;
      std::printf(
          "[ measured ] PX4 fleet, GCS instance %d: system %d's first heartbeat %d ms of the "
          "vehicles' clock after the first message heard, %d ms wall after binding\n",
          instance, id, clock.at(id), wall.at(id));
    }
  }
  const std::string summary = ReadAll(out + "/summary.json");
  EXPECT_GT(SummaryNumber(summary, "\"gcs_relay\":", "\"to_gcs_unreceived\":"), 0) << summary;

  // The truth: the flown vehicle held the altitude above where it armed (within issue 31's 0.3 m
  // from HOLD's steady start to its end); the others stayed where they started.
  const std::map<std::string, FlightEvent> events =
      FlightEvents(flown_log, "sys=" + std::to_string(kFlown) + " ");
  ASSERT_EQ(events.count("ARMED"), 1u) << flown_log.substr(0, 4000);
  ASSERT_EQ(events.count("HOLD"), 1u) << flown_log.substr(0, 4000);
  const std::string csv = ReadAll(out + "/trajectories.csv");
  std::map<std::string, std::string> sent = UdpPayloads(out, "udp and src host " + WlanAddress(0),
                                                        "ip.src == " + WlanAddress(0), "ip.dst");
  for (int id = 1; id <= kVehicles; ++id) {
    const std::vector<TrajectoryRow> rows = TrajectoryRows(csv, id);
    ASSERT_FALSE(rows.empty()) << "uav" << id;
    double highest_m = 0;
    for (const TrajectoryRow& row : rows) highest_m = std::max(highest_m, row.z_m - rows[0].z_m);
    double altitude_error_m = 0;
    int rows_held = 0;
    const Crossed commands =
        DecodeMavlink(sent[WlanAddress(id)], out + "-to" + std::to_string(id) + ".bin");
    if (id == kFlown) {
      const double armed_z_m = RowAt(rows, events.at("ARMED").t_s).z_m;
      for (const TrajectoryRow& row : rows) {
        if (row.t_s < events.at("HOLD").since_s || row.t_s >= events.at("HOLD").t_s) continue;
        altitude_error_m = std::max(altitude_error_m, std::fabs(row.z_m - armed_z_m - kAltitudeM));
        ++rows_held;
      }
      EXPECT_GT(rows_held, 20) << "uav" << id;
      EXPECT_LT(altitude_error_m, 0.3) << "uav" << id;
      EXPECT_GT(commands.CommandsTo(id, 400), 0) << "uav" << id << ": COMPONENT_ARM_DISARM";
      EXPECT_GT(commands.CommandsTo(id, 22), 0) << "uav" << id << ": NAV_TAKEOFF";
    } else {
      // On its landing gear: the simulated contact settles within centimetres.
      EXPECT_LT(highest_m, 0.1) << "uav" << id;
      for (int other = 1; other <= kVehicles; ++other) {
        EXPECT_EQ(commands.CommandsTo(other, 400), 0) << "to uav" << id << " for system " << other;
        EXPECT_EQ(commands.CommandsTo(other, 22), 0) << "to uav" << id << " for system " << other;
      }
    }
    std::printf(
        "[ measured ] PX4 fleet, restarted GCS flying uav%d: uav%d rose %.3f m at most; held "
        "%d rows within %.3f m of %.0f m\n",
        kFlown, id, highest_m, rows_held, altitude_error_m, kAltitudeM);
  }
  ExpectNothingLeft("px4fleet");
  if (!::testing::Test::HasFailure()) {
    RunCommand({"rm", "-rf", out, flown_output});
    for (int id = 1; id <= kVehicles; ++id) {
      RunCommand({"rm", "-f", out + "-to" + std::to_string(id) + ".bin"});
    }
  }
}

}  // namespace
}  // namespace sitlnet::nns::testing

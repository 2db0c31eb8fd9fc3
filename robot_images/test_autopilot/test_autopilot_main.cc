// test_autopilot: a small autopilot for sitlnet's tests and demos (issue 14), standing in for
// ArduPilot SITL and PX4 SITL where neither can be installed. It speaks either autopilot's
// simulator protocol as that autopilot does (json_autopilot_link.h: ArduPilot's JSON;
// px4_autopilot_link.h: PX4's simulator MAVLink), takes its clock from the simulator's messages,
// arms after --arm-after-s of that clock once the protocol gave what flying needs, climbs to an
// altitude, holds it and flies to a waypoint (pilot.h), and sends MAVLink telemetry (HEARTBEAT,
// GLOBAL_POSITION_INT) to a ground station on the radio (telemetry.h).
//
// Usage: test_autopilot (--json-port PORT [--rate-hz 400] | --px4-port PORT)
//          [--altitude-m 10] [--waypoint X,Y] [--origin LAT,LON,ALT] [--arm-after-s 0.5]
//          [--telemetry ADDR:PORT] [--telemetry-hz 10] [--log-replies] [--stop-after-s S]
// The simulator is at the address of SITLNET_PHYSICS_ADDR (the root side of ctl0), at PORT.
// --origin: the geodetic origin of sitlnet's world frame (the scenario's geodetic_origin; by
//   default sitlnet's default); waypoints and altitude are in that frame.
// --arm-after-s: as an autopilot waits for its estimator before it arms. In PX4's protocol the
//   answers before PX4's first are not awaited (docs/autopilots.md), so nothing the autopilot
//   does before it arms should move the vehicle.
// --log-replies: one line per observation: "reply N t=S pos=X,Y,Z wall_ns=W" (the simulator's
//   truth; W: CLOCK_MONOTONIC when the observation was taken).
// --stop-after-s: exits once its clock has passed S (a crashed autopilot, for tests).
// MAVLink system id: SITLNET_ROBOT_INDEX + 1.
#include <arpa/inet.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>

#include "robot_images/test_autopilot/json_autopilot_link.h"
#include "robot_images/test_autopilot/pilot.h"
#include "robot_images/test_autopilot/px4_autopilot_link.h"
#include "robot_images/test_autopilot/telemetry.h"

namespace {

using namespace sitlnet::test_autopilot;

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "test_autopilot: %s\n", message.c_str());
  std::exit(2);
}

constexpr int kConnectTimeoutMs = 30000;

struct Options {
  uint16_t json_port = 0;
  uint16_t px4_port = 0;
  uint16_t rate_hz = 400;
  Mission mission;
  GeodeticPosition origin{47.397742, 8.545594, 488};  // scenario.proto's default origin
  double arm_after_s = 0.5;
  std::string telemetry;  // ADDR:PORT, empty: none
  double telemetry_hz = 10;
  bool log_replies = false;
  double stop_after_s = 0;  // 0: never
};

sockaddr_in ParseAddress(const std::string& text, const char* what) {
  const size_t colon = text.rfind(':');
  sockaddr_in address{};
  address.sin_family = AF_INET;
  if (colon == std::string::npos ||
      inet_pton(AF_INET, text.substr(0, colon).c_str(), &address.sin_addr) != 1) {
    Die(std::string(what) + ": expected IPv4:PORT, got \"" + text + "\"");
  }
  address.sin_port = htons(static_cast<uint16_t>(std::atoi(text.c_str() + colon + 1)));
  return address;
}

Options ParseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) Die(flag + " needs a value");
      return argv[++i];
    };
    if (flag == "--json-port") {
      options.json_port = static_cast<uint16_t>(std::atoi(value().c_str()));
    } else if (flag == "--px4-port") {
      options.px4_port = static_cast<uint16_t>(std::atoi(value().c_str()));
    } else if (flag == "--rate-hz") {
      options.rate_hz = static_cast<uint16_t>(std::atoi(value().c_str()));
    } else if (flag == "--altitude-m") {
      options.mission.altitude_m = std::atof(value().c_str());
    } else if (flag == "--waypoint") {
      const std::string text = value();
      Eigen::Vector2d waypoint;
      if (std::sscanf(text.c_str(), "%lf,%lf", &waypoint.x(), &waypoint.y()) != 2) {
        Die("--waypoint: expected X,Y in metres, got \"" + text + "\"");
      }
      options.mission.waypoint_m = waypoint;
    } else if (flag == "--origin") {
      const std::string text = value();
      GeodeticPosition& o = options.origin;
      if (std::sscanf(text.c_str(), "%lf,%lf,%lf", &o.latitude_deg, &o.longitude_deg,
                      &o.altitude_m) != 3) {
        Die("--origin: expected LAT,LON,ALT in degrees and metres, got \"" + text + "\"");
      }
    } else if (flag == "--arm-after-s") {
      options.arm_after_s = std::atof(value().c_str());
    } else if (flag == "--telemetry") {
      options.telemetry = value();
    } else if (flag == "--telemetry-hz") {
      options.telemetry_hz = std::atof(value().c_str());
    } else if (flag == "--stop-after-s") {
      options.stop_after_s = std::atof(value().c_str());
    } else if (flag == "--log-replies") {
      options.log_replies = true;
    } else {
      Die("unknown flag " + flag);
    }
  }
  if ((options.json_port == 0) == (options.px4_port == 0)) {
    Die("exactly one of --json-port and --px4-port is required");
  }
  if (options.rate_hz < 50 || options.rate_hz > 1000) Die("--rate-hz must be in [50, 1000]");
  if (!(options.telemetry_hz > 0)) Die("--telemetry-hz must be > 0");
  return options;
}

int Run(const Options& options) {
  const char* physics = std::getenv("SITLNET_PHYSICS_ADDR");
  if (physics == nullptr) Die("SITLNET_PHYSICS_ADDR is not set (run me in a sitlnet robot)");
  sockaddr_in server = ParseAddress(physics, "SITLNET_PHYSICS_ADDR");
  const char* index = std::getenv("SITLNET_ROBOT_INDEX");
  const auto system_id = static_cast<uint8_t>(1 + (index ? std::atoi(index) : 0));
  const LocalFrame frame(options.origin);
  std::unique_ptr<SimulatorLink> link;
  if (options.json_port != 0) {
    server.sin_port = htons(options.json_port);
    link = std::make_unique<JsonLink>(server, options.rate_hz);
  } else {
    server.sin_port = htons(options.px4_port);
    link = std::make_unique<Px4Link>(server, system_id, &frame, kConnectTimeoutMs);
  }
  std::unique_ptr<Telemetry> telemetry;
  if (!options.telemetry.empty()) {
    telemetry = std::make_unique<Telemetry>(ParseAddress(options.telemetry, "--telemetry"),
                                            system_id, &frame, options.telemetry_hz);
  }
  Pilot pilot(options.mission);
  bool armed = false;
  for (uint64_t observations = 0; !g_stop;) {
    Observation observation;
    // Short waits: SIGTERM is noticed within 100 ms.
    if (link->Wait(100, &observation) != SimulatorLink::Result::kObservation) continue;
    ++observations;
    if (options.stop_after_s > 0 && observation.time_s >= options.stop_after_s) {
      std::printf("stopping at t=%.6f as asked\n", observation.time_s);
      break;
    }
    armed = armed || (observation.ready_to_arm && observation.time_s >= options.arm_after_s);
    const MotorOutputs motors = armed ? pilot.Fly(observation.state) : MotorOutputs{};
    // From arming on (before it, PX4's protocol leaves the timing of the first answers to the
    // host: docs/autopilots.md), and before the answer: in lockstep pacing the datagrams enter
    // the medium in this iteration.
    if (telemetry && armed) telemetry->Update(observation, armed);
    if (options.log_replies) {
      const Eigen::Vector3d& p = observation.true_position_m;
      timespec now{};
      clock_gettime(CLOCK_MONOTONIC, &now);
      std::printf("reply %llu t=%.6f pos=%.6f,%.6f,%.6f wall_ns=%lld\n",
                  static_cast<unsigned long long>(observations), observation.time_s, p.x(), p.y(),
                  p.z(), static_cast<long long>(now.tv_sec) * 1000000000LL + now.tv_nsec);
    }
    link->Answer(motors, armed);
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGINT, OnSignal);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  return Run(ParseOptions(argc, argv));
}

// test_autopilot: a small autopilot for sitlnet's tests and demos (issue 14), standing in for
// ArduPilot SITL where no ArduPilot binary can be installed. It speaks ArduPilot's JSON physics
// protocol exactly as SITL does (docs/protocols.md): a 40-byte servo frame with an increasing
// frame_count, then it waits for the reply, whose timestamp is its clock, and sends the same
// frame again when no reply comes within a second. From the reply alone (position, velocity,
// attitude, gyro) it climbs to an altitude, holds it and flies to a waypoint with the flocker's
// cascaded controller. It sends a telemetry datagram on the radio at a rate of its own clock.
//
// Usage: test_autopilot --json-port PORT [--rate-hz 400] [--altitude-m 10] [--waypoint X,Y]
//          [--telemetry ADDR:PORT] [--telemetry-hz 10] [--log-replies] [--stop-after-s S]
// --stop-after-s: exits once its clock has passed S (a crashed autopilot, for tests).
// The server is the address of SITLNET_PHYSICS_ADDR (the root side of ctl0) at PORT.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "robot_images/flocker/controller.h"

namespace {

using sitlnet::flocker::AirframeParams;
using sitlnet::flocker::ComputeRotorSpeeds;
using sitlnet::flocker::ControllerGains;
using sitlnet::flocker::VehicleState;

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "test_autopilot: %s\n", message.c_str());
  std::exit(2);
}

struct Options {
  uint16_t json_port = 0;
  uint16_t rate_hz = 400;
  double altitude_m = 10;
  Eigen::Vector2d waypoint_m{0, 0};
  bool has_waypoint = false;
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
    } else if (flag == "--rate-hz") {
      options.rate_hz = static_cast<uint16_t>(std::atoi(value().c_str()));
    } else if (flag == "--altitude-m") {
      options.altitude_m = std::atof(value().c_str());
    } else if (flag == "--waypoint") {
      const std::string text = value();
      if (std::sscanf(text.c_str(), "%lf,%lf", &options.waypoint_m.x(), &options.waypoint_m.y()) !=
          2) {
        Die("--waypoint: expected X,Y in metres, got \"" + text + "\"");
      }
      options.has_waypoint = true;
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
  if (options.json_port == 0) Die("--json-port is required");
  if (options.rate_hz < 50 || options.rate_hz > 1000) Die("--rate-hz must be in [50, 1000]");
  if (!(options.telemetry_hz > 0)) Die("--telemetry-hz must be > 0");
  return options;
}

// The servo frame of ArduPilot's JSON backend: magic 18458, frame rate, frame count, 16 PWMs
// (µs), little-endian.
std::string ServoFrame(uint16_t rate_hz, uint32_t frame_count, const std::array<double, 4>& pwm) {
  std::string bytes(40, '\0');
  const auto put16 = [&](int at, uint16_t v) {
    bytes[at] = static_cast<char>(v & 0xff);
    bytes[at + 1] = static_cast<char>(v >> 8);
  };
  put16(0, 18458);
  put16(2, rate_hz);
  for (int i = 0; i < 4; ++i) bytes[4 + i] = static_cast<char>((frame_count >> (8 * i)) & 0xff);
  for (int channel = 0; channel < 16; ++channel) {
    put16(8 + 2 * channel,
          channel < 4 ? static_cast<uint16_t>(std::clamp(pwm[channel], 1000.0, 2000.0)) : 1500);
  }
  return bytes;
}

// The numbers of `"key":` (one, or an array) in the reply, as ArduPilot's parser finds keys.
bool ReadNumbers(const std::string& json, const char* key, double* out, int count) {
  const std::string quoted = std::string("\"") + key + "\":";
  const size_t at = json.find(quoted);
  if (at == std::string::npos) return false;
  const char* p = json.c_str() + at + quoted.size();
  if (count > 1 && *p++ != '[') return false;
  for (int i = 0; i < count; ++i) {
    char* end = nullptr;
    out[i] = std::strtod(p, &end);
    if (end == p) return false;
    p = end + 1;
  }
  return true;
}

struct Reply {
  double timestamp_s = 0;
  VehicleState state;  // world ENU, body FLU, as the flocker's controller expects
};

// NED/FRD (the protocol's frames) to ENU/FLU.
bool ParseReply(const std::string& json, Reply* reply) {
  double t = 0, gyro[3], position[3], velocity[3], q[4];
  if (!ReadNumbers(json, "timestamp", &t, 1) || !ReadNumbers(json, "gyro", gyro, 3) ||
      !ReadNumbers(json, "position", position, 3) || !ReadNumbers(json, "velocity", velocity, 3) ||
      !ReadNumbers(json, "quaternion", q, 4)) {
    return false;
  }
  reply->timestamp_s = t;
  reply->state.position_m = {position[1], position[0], -position[2]};
  reply->state.velocity_m_s = {velocity[1], velocity[0], -velocity[2]};
  reply->state.angular_velocity_rad_s = {gyro[0], -gyro[1], -gyro[2]};
  // body FLU -> world ENU = (NED -> ENU) * (FRD -> NED) * (FLU -> FRD).
  const Eigen::Quaterniond ned_to_enu(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d(1, 1, 0).normalized()));
  const Eigen::Quaterniond flu_to_frd(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  reply->state.orientation = ned_to_enu * Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * flu_to_frd;
  reply->state.orientation.normalize();
  return true;
}

double Yaw(const Eigen::Quaterniond& q) {
  return std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
}

int Run(const Options& options) {
  const char* physics = std::getenv("SITLNET_PHYSICS_ADDR");
  if (physics == nullptr) Die("SITLNET_PHYSICS_ADDR is not set (run me in a sitlnet robot)");
  sockaddr_in server = ParseAddress(physics, "SITLNET_PHYSICS_ADDR");
  server.sin_port = htons(options.json_port);
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&server), sizeof server) != 0) {
    Die(std::string("JSON socket: ") + std::strerror(errno));
  }
  int telemetry_fd = -1;
  sockaddr_in telemetry{};
  if (!options.telemetry.empty()) {
    telemetry = ParseAddress(options.telemetry, "--telemetry");
    telemetry_fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    // A fixed source port (the destination's, as MAVLink peers use) and path-MTU discovery "do"
    // (DF set, IP ID 0 on unconnected datagrams): nothing of the kernel's randomness reaches
    // the capture, so lockstep runs give byte-identical captures.
    const int pmtu_do = IP_PMTUDISC_DO;
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = telemetry.sin_port;
    if (setsockopt(telemetry_fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) != 0 ||
        setsockopt(telemetry_fd, IPPROTO_IP, IP_MTU_DISCOVER, &pmtu_do, sizeof pmtu_do) != 0 ||
        bind(telemetry_fd, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
      Die(std::string("telemetry socket: ") + std::strerror(errno));
    }
  }
  const AirframeParams airframe;  // sitlnet's default quad (scenario.proto's Airframe defaults)
  const ControllerGains gains;
  const double telemetry_period_s = 1 / options.telemetry_hz;
  double next_telemetry_s = 0;
  double yaw_rad = NAN;
  uint32_t frame_count = 1;
  std::array<double, 4> pwm{1000, 1000, 1000, 1000};  // motors stopped until the first state
  std::string frame = ServoFrame(options.rate_hz, frame_count, pwm);
  send(fd, frame.data(), frame.size(), 0);
  int waited_ms = 0;
  while (!g_stop) {
    pollfd wait{fd, POLLIN, 0};
    if (poll(&wait, 1, 100) <= 0) {  // Short waits: SIGTERM is noticed within 100 ms.
      waited_ms += 100;
      if (waited_ms >= 1000) {  // As SITL does: the same frame again.
        send(fd, frame.data(), frame.size(), 0);
        waited_ms = 0;
      }
      continue;
    }
    waited_ms = 0;
    char buffer[2048];
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    Reply reply;
    if (n <= 0 || !ParseReply(std::string(buffer, n), &reply)) continue;
    if (options.stop_after_s > 0 && reply.timestamp_s >= options.stop_after_s) {
      std::printf("stopping at t=%.6f as asked\n", reply.timestamp_s);
      break;
    }
    const VehicleState& vehicle = reply.state;
    if (std::isnan(yaw_rad)) yaw_rad = Yaw(vehicle.orientation);
    Eigen::Vector2d velocity_xy = Eigen::Vector2d::Zero();
    const bool at_altitude = vehicle.position_m.z() > 0.8 * options.altitude_m;
    if (options.has_waypoint && at_altitude) {
      const Eigen::Vector2d to_go = options.waypoint_m - vehicle.position_m.head<2>();
      velocity_xy = 0.5 * to_go;
      if (velocity_xy.norm() > 2) velocity_xy *= 2 / velocity_xy.norm();
    }
    const auto speeds =
        ComputeRotorSpeeds(airframe, gains, vehicle, velocity_xy, options.altitude_m, yaw_rad);
    for (int i = 0; i < 4; ++i) pwm[i] = 1000 + 1000 * speeds[i] / airframe.max_rotor_speed_rad_s;
    if (telemetry_fd >= 0 && reply.timestamp_s >= next_telemetry_s) {
      // Before the next frame: in lockstep pacing it enters the medium in this iteration.
      char text[160];
      const int length = std::snprintf(
          text, sizeof text, "test_autopilot t=%.6f pos=%.3f,%.3f,%.3f", reply.timestamp_s,
          vehicle.position_m.x(), vehicle.position_m.y(), vehicle.position_m.z());
      sendto(telemetry_fd, text, length, 0, reinterpret_cast<sockaddr*>(&telemetry),
             sizeof telemetry);
      next_telemetry_s += telemetry_period_s;
    }
    if (options.log_replies) {
      std::printf("reply %u t=%.6f pos=%.6f,%.6f,%.6f\n", frame_count, reply.timestamp_s,
                  vehicle.position_m.x(), vehicle.position_m.y(), vehicle.position_m.z());
    }
    frame = ServoFrame(options.rate_hz, ++frame_count, pwm);
    send(fd, frame.data(), frame.size(), 0);
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

#include "robot_images/test_autopilot/telemetry.h"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "mavlink/mavlink.h"

namespace sitlnet::test_autopilot {
namespace {

int16_t CentimetresPerSecond(double metres_per_second) {
  return static_cast<int16_t>(std::clamp(std::lround(metres_per_second * 100), -32767L, 32767L));
}

}  // namespace

Telemetry::Telemetry(const sockaddr_in& to, uint8_t system_id, const LocalFrame* frame,
                     double rate_hz)
    : to_(to), system_id_(system_id), frame_(frame), period_s_(1 / rate_hz) {
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  // A fixed source port (the destination's, as MAVLink peers use) and path-MTU discovery "do"
  // (DF set, IP ID 0 on unconnected datagrams): nothing of the kernel's randomness reaches
  // the capture, so lockstep runs give byte-identical captures.
  const int pmtu_do = IP_PMTUDISC_DO;
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_port = to.sin_port;
  if (fd_ < 0 || setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) != 0 ||
      setsockopt(fd_, IPPROTO_IP, IP_MTU_DISCOVER, &pmtu_do, sizeof pmtu_do) != 0 ||
      bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
    std::fprintf(stderr, "test_autopilot: telemetry socket: %s\n", std::strerror(errno));
    std::exit(2);
  }
}

Telemetry::~Telemetry() { close(fd_); }

void Telemetry::Send(const std::vector<uint8_t>& bytes) {
  sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_);
  ++sequence_;
}

void Telemetry::Update(const Observation& observation, bool armed) {
  // A nanosecond's slack: time_usec * 1e-6 can fall just short of a multiple of the period.
  const double t = observation.time_s + 1e-9;
  const mavlink::Header header{sequence_, system_id_, 1};  // MAV_COMP_ID_AUTOPILOT1
  std::vector<uint8_t> bytes;
  if (t >= next_heartbeat_s_) {
    mavlink::Heartbeat heartbeat;
    heartbeat.type = 2;       // MAV_TYPE_QUADROTOR
    heartbeat.autopilot = 0;  // MAV_AUTOPILOT_GENERIC: neither PX4 nor ArduPilot
    heartbeat.base_mode = armed ? mavlink::kModeFlagSafetyArmed : 0;
    heartbeat.system_status = armed ? 4 : 3;  // MAV_STATE_ACTIVE : MAV_STATE_STANDBY
    mavlink::AppendMessage(heartbeat, header, &bytes);
    Send(bytes);
    while (next_heartbeat_s_ <= t) next_heartbeat_s_ += 1;
  }
  if (t >= next_position_s_ && observation.ready_to_arm) {
    const flocker::VehicleState& state = observation.state;
    const GeodeticPosition where = frame_->ToGeodetic(state.position_m);
    mavlink::GlobalPositionInt position;
    position.time_boot_ms = static_cast<uint32_t>(std::llround(std::floor(t * 1e3 + 1e-6)));
    position.lat = static_cast<int32_t>(std::lround(where.latitude_deg * 1e7));
    position.lon = static_cast<int32_t>(std::lround(where.longitude_deg * 1e7));
    position.alt = static_cast<int32_t>(std::lround(where.altitude_m * 1e3));
    position.relative_alt =
        static_cast<int32_t>(std::lround((where.altitude_m - frame_->origin().altitude_m) * 1e3));
    position.vx = CentimetresPerSecond(state.velocity_m_s.y());   // north
    position.vy = CentimetresPerSecond(state.velocity_m_s.x());   // east
    position.vz = CentimetresPerSecond(-state.velocity_m_s.z());  // down
    const Eigen::Vector3d nose = state.orientation * Eigen::Vector3d::UnitX();
    const double heading_deg = std::atan2(nose.x(), nose.y()) * 180 / M_PI;  // from north
    position.hdg =
        static_cast<uint16_t>(std::lround(std::fmod(heading_deg + 360, 360) * 100) % 36000);
    bytes.clear();
    mavlink::AppendMessage(position, {sequence_, system_id_, 1}, &bytes);
    Send(bytes);
    while (next_position_s_ <= t) next_position_s_ += period_s_;
  }
}

}  // namespace sitlnet::test_autopilot

#include "robot_images/test_autopilot/px4_autopilot_link.h"

#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sitlnet::test_autopilot {
namespace {

constexpr uint64_t kHeartbeatPeriodUsec = 1000000;
constexpr uint8_t kFix3d = 3;  // GPS_FIX_TYPE_3D_FIX

[[noreturn]] void Die(const char* what) {
  std::fprintf(stderr, "test_autopilot: PX4 link: %s\n", what);
  std::exit(2);
}

}  // namespace

Px4Link::Px4Link(const sockaddr_in& server, uint8_t system_id, const LocalFrame* frame,
                 int connect_timeout_ms)
    : system_id_(system_id), frame_(frame) {
  for (int waited_ms = 0;; waited_ms += 100) {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) Die(std::strerror(errno));
    if (connect(fd_, reinterpret_cast<const sockaddr*>(&server), sizeof server) == 0) break;
    const int error = errno;
    close(fd_);
    if (waited_ms >= connect_timeout_ms) Die(std::strerror(error));
    poll(nullptr, 0, 100);  // Not yet listening: try again, as PX4 does.
  }
  const int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

Px4Link::~Px4Link() { close(fd_); }

void Px4Link::Write(const std::vector<uint8_t>& bytes) {
  if (send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(bytes.size())) {
    Die("the simulator closed the connection");
  }
}

bool Px4Link::Take(const mavlink::ReceivedFrame& frame, Observation* observation) {
  mavlink::HilSensor sensor;
  mavlink::HilGps gps;
  mavlink::HilStateQuaternion truth;
  if (mavlink::Unpack(frame, &sensor)) {
    sensor_ = sensor;
    return false;
  }
  if (mavlink::Unpack(frame, &gps)) {
    if (gps.fix_type >= kFix3d) fix_ = gps;
    return false;
  }
  if (!mavlink::Unpack(frame, &truth) || !sensor_ || truth.time_usec != sensor_->time_usec) {
    return false;
  }
  const double time_s = sensor_->time_usec * 1e-6;
  observation->time_s = time_s;
  flocker::VehicleState& state = observation->state;
  const auto& q = truth.attitude_quaternion;
  state.orientation = FrdInNedToFluInEnu(Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
  state.angular_velocity_rad_s = FrdToFlu({sensor_->xgyro, sensor_->ygyro, sensor_->zgyro});
  observation->true_position_m =
      frame_->ToEnu({truth.lat * 1e-7, truth.lon * 1e-7, truth.alt * 1e-3});
  observation->ready_to_arm = fix_.has_value();
  if (fix_) {
    state.velocity_m_s = NedToEnu({fix_->vn * 1e-2, fix_->ve * 1e-2, fix_->vd * 1e-2});
    const double age_s = time_s - fix_->time_usec * 1e-6;
    state.position_m = frame_->ToEnu({fix_->lat * 1e-7, fix_->lon * 1e-7, fix_->alt * 1e-3}) +
                       age_s * state.velocity_m_s;
  }
  answering_usec_ = sensor_->time_usec;
  sensor_.reset();
  return true;
}

SimulatorLink::Result Px4Link::Wait(int timeout_ms, Observation* observation) {
  mavlink::ReceivedFrame frame;
  for (;;) {
    while (parser_.Next(&frame)) {
      if (Take(frame, observation)) return Result::kObservation;
    }
    pollfd wait{fd_, POLLIN, 0};
    if (poll(&wait, 1, timeout_ms) <= 0) return Result::kTimeout;
    uint8_t buffer[4096];
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) Die("the simulator closed the connection");
    parser_.Push(buffer, static_cast<size_t>(n));
  }
}

void Px4Link::Answer(const MotorOutputs& motors, bool armed) {
  std::vector<uint8_t> bytes;
  const mavlink::Header header{sequence_, system_id_, 1};  // MAV_COMP_ID_AUTOPILOT1
  if (answering_usec_ >= next_heartbeat_usec_) {
    mavlink::Heartbeat heartbeat;
    heartbeat.type = 2;        // MAV_TYPE_QUADROTOR
    heartbeat.autopilot = 12;  // MAV_AUTOPILOT_PX4: what PX4 says of itself
    heartbeat.base_mode = armed ? mavlink::kModeFlagSafetyArmed : 0;
    heartbeat.system_status = armed ? 4 : 3;  // MAV_STATE_ACTIVE : MAV_STATE_STANDBY
    mavlink::AppendMessage(heartbeat, header, &bytes);
    ++sequence_;
    next_heartbeat_usec_ = answering_usec_ + kHeartbeatPeriodUsec;
  }
  mavlink::HilActuatorControls controls;
  controls.time_usec = answering_usec_;
  controls.flags = mavlink::kActuatorFlagLockstep;
  for (int i = 0; i < 4; ++i) controls.controls[i] = armed ? static_cast<float>(motors[i]) : 0;
  controls.mode = armed ? mavlink::kModeFlagSafetyArmed : 0;
  mavlink::AppendMessage(controls, {sequence_, system_id_, 1}, &bytes);
  ++sequence_;
  Write(bytes);
}

}  // namespace sitlnet::test_autopilot

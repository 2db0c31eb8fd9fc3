#include "physics_mujoco/px4_simulator_link.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "physics_mujoco/px4_messages.h"
#include "physics_mujoco/udp_socket.h"

namespace sitlnet::physics {
namespace {

// The ids sitlnet sends with: PX4's Gazebo interface uses system 1, component 200
// (MAV_COMP_ID_IMU); PX4 does not check them.
constexpr mavlink::Header kSimulatorIds{0, 1, 200};
constexpr uint64_t kHeartbeatPeriodUsec = 1000000;
// PX4 reads in lock-step; this much unread output means it stopped reading: later messages are
// dropped (counted) instead of growing without bound.
constexpr size_t kMaxBacklogBytes = 1 << 20;

void CloseFd(int* fd) {
  if (*fd >= 0) close(*fd);
  *fd = -1;
}

void Add(mavlink::ParserCounters* sum, const mavlink::ParserCounters& more) {
  sum->frames += more.frames;
  sum->bytes_skipped += more.bytes_skipped;
  sum->bad_crc += more.bad_crc;
  sum->bad_length += more.bad_length;
  sum->unknown_messages += more.unknown_messages;
  sum->mavlink1_frames += more.mavlink1_frames;
}

}  // namespace

Px4SimulatorLink::Px4SimulatorLink(Ipv4 address, uint16_t port, double max_rotor_speed_rad_s,
                                   const std::string& what)
    : what_(what), max_rotor_speed_rad_s_(max_rotor_speed_rad_s) {
  const std::string where =
      what + ": listen TCP " + FormatIpv4(address) + ":" + std::to_string(port);
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw Error(SystemErrorMessage(where, errno));
  const int one = 1;
  const sockaddr_in sa = MakeSockaddr(address, port);
  if (setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
      setsockopt(listen_fd_, IPPROTO_IP, IP_FREEBIND, &one, sizeof one) != 0 ||
      bind(listen_fd_, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0 ||
      listen(listen_fd_, 4) != 0) {
    const int err = errno;
    CloseFd(&listen_fd_);
    throw Error(SystemErrorMessage(where, err));
  }
}

Px4SimulatorLink::~Px4SimulatorLink() {
  CloseFd(&connection_fd_);
  CloseFd(&listen_fd_);
}

uint16_t Px4SimulatorLink::port() const {
  sockaddr_in sa{};
  socklen_t length = sizeof sa;
  SITLNET_DEMAND(getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &length) == 0);
  return ntohs(sa.sin_port);
}

const Px4LinkCounters& Px4SimulatorLink::counters() const {
  counters_.parser = parser_before_;
  Add(&counters_.parser, parser_.counters());
  return counters_;
}

void Px4SimulatorLink::Disconnect() {
  if (connection_fd_ < 0) return;
  lost_in_lockstep_ = controls_since_connect_ && command_.lockstep;
  CloseFd(&connection_fd_);
  ++counters_.disconnections;
  Add(&parser_before_, parser_.counters());
  parser_ = mavlink::FrameParser();
  outgoing_.clear();
  command_ = Px4Command();  // Motors stop, as PX4's outputs do when it dies.
  sensor_sent_ = false;
  controls_since_connect_ = false;
  next_heartbeat_usec_ = 0;
}

Px4SimulatorLink::Event Px4SimulatorLink::Poll() {
  const Event event = Accept();
  Read();
  return event;
}

Px4SimulatorLink::Event Px4SimulatorLink::Accept() {
  Event event = Event::kNone;
  // The newest waiting connection wins: PX4 restarted, and its old connection is dead.
  for (;;) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) break;
    const bool replacing =
        connection_fd_ >= 0 || event != Event::kNone || counters_.connections > 0;
    Disconnect();
    lost_in_lockstep_ = false;
    connection_fd_ = fd;
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);  // as PX4 sets on its side
    ++counters_.connections;
    if (replacing) ++counters_.reconnections;
    event = replacing ? Event::kReconnected : Event::kConnected;
  }
  return event;
}

void Px4SimulatorLink::Read() {
  if (connection_fd_ < 0) return;
  uint8_t buffer[4096];
  for (;;) {
    const ssize_t n = recv(connection_fd_, buffer, sizeof buffer, 0);
    if (n > 0) {
      parser_.Push(buffer, static_cast<size_t>(n));
      // A short read took all that was queued: no second recv to hear EAGAIN (one system call
      // per answer). What arrives later makes the fd readable again (level-triggered epoll).
      if (static_cast<size_t>(n) < sizeof buffer) break;
      continue;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) Disconnect();
    if (n < 0 && errno == EINTR) continue;
    break;
  }
  mavlink::ReceivedFrame frame;
  while (parser_.Next(&frame)) Take(frame);
  Flush();
}

void Px4SimulatorLink::Take(const mavlink::ReceivedFrame& frame) {
  mavlink::HilActuatorControls controls;
  mavlink::Heartbeat heartbeat;
  if (mavlink::Unpack(frame, &controls)) {
    const std::optional<RotorSpeeds> speeds = RotorSpeedsOf(controls, max_rotor_speed_rad_s_);
    if (!speeds) {
      ++counters_.dropped_invalid;
      return;
    }
    command_ = {*speeds, (controls.mode & mavlink::kModeFlagSafetyArmed) != 0, controls.time_usec,
                (controls.flags & mavlink::kActuatorFlagLockstep) != 0};
    ++counters_.actuator_controls;
    controls_since_connect_ = true;
  } else if (mavlink::Unpack(frame, &heartbeat)) {
    ++counters_.heartbeats_received;
  } else {
    ++counters_.ignored;
  }
}

bool Px4SimulatorLink::awaiting_answer() const {
  if (lost_in_lockstep_) return true;
  return connection_fd_ >= 0 && controls_since_connect_ && command_.lockstep && sensor_sent_ &&
         !answered_last_sensor();
}

bool Px4SimulatorLink::answered_last_sensor() const {
  return sensor_sent_ && counters_.actuator_controls > 0 && command_.time_usec == last_sensor_usec_;
}

template <typename Message>
void Px4SimulatorLink::Append(const Message& message) {
  mavlink::Header header = kSimulatorIds;
  header.sequence = sequence_++;
  mavlink::AppendMessage(message, header, &outgoing_);
}

void Px4SimulatorLink::Send(const mavlink::HilSensor& sensor, const mavlink::HilGps* gps,
                            const mavlink::HilStateQuaternion* ground_truth) {
  if (connection_fd_ < 0 || outgoing_.size() > kMaxBacklogBytes) {
    ++counters_.send_errors;
    return;
  }
  if (sensor.time_usec >= next_heartbeat_usec_) {
    // MAV_TYPE_GENERIC, MAV_AUTOPILOT_INVALID (not a flight controller), MAV_STATE_ACTIVE.
    mavlink::Heartbeat heartbeat;
    heartbeat.autopilot = 8;
    heartbeat.system_status = 4;
    Append(heartbeat);
    ++counters_.heartbeats_sent;
    next_heartbeat_usec_ = sensor.time_usec + kHeartbeatPeriodUsec;
  }
  Append(sensor);
  ++counters_.sensors_sent;
  last_sensor_usec_ = sensor.time_usec;
  sensor_sent_ = true;
  if (gps) {
    Append(*gps);
    ++counters_.gps_sent;
  }
  if (ground_truth) {
    Append(*ground_truth);
    ++counters_.ground_truth_sent;
  }
  Flush();
}

void Px4SimulatorLink::Flush() {
  size_t sent = 0;
  while (connection_fd_ >= 0 && sent < outgoing_.size()) {
    const ssize_t n = send(connection_fd_, outgoing_.data() + sent, outgoing_.size() - sent,
                           MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      sent += static_cast<size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) Disconnect();
      break;
    }
  }
  if (connection_fd_ >= 0) {
    outgoing_.erase(outgoing_.begin(), outgoing_.begin() + static_cast<std::ptrdiff_t>(sent));
  }
}

}  // namespace sitlnet::physics

// The simulator side of PX4's simulator MAVLink interface for one robot (docs/autopilots.md,
// "PX4 simulator interface"): a TCP server PX4 connects to, the sensor messages sitlnet sends,
// the actuator outputs it takes. Clock-agnostic: the caller says when to send and at which
// virtual time; nothing here blocks.
#ifndef SITLNET_PHYSICS_MUJOCO_PX4_SIMULATOR_LINK_H_
#define SITLNET_PHYSICS_MUJOCO_PX4_SIMULATOR_LINK_H_

#include <cstdint>
#include <string>
#include <vector>

#include "mavlink/mavlink.h"
#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

// Per-link counters. Every received byte that is not part of a used frame is counted in the
// parser's counters or in `ignored` / `dropped_invalid`.
struct Px4LinkCounters {
  uint64_t connections = 0;        // Accepted connections.
  uint64_t reconnections = 0;      // Of those, ones that replaced a previous connection.
  uint64_t disconnections = 0;     // Closed by PX4 (or reset).
  uint64_t actuator_controls = 0;  // HIL_ACTUATOR_CONTROLS taken.
  uint64_t heartbeats_received = 0;
  uint64_t ignored = 0;            // Valid messages sitlnet does not act on (COMMAND_LONG, ...).
  uint64_t dropped_invalid = 0;    // HIL_ACTUATOR_CONTROLS with a non-finite motor output.
  mavlink::ParserCounters parser;  // Summed over connections.
  uint64_t sensors_sent = 0;
  uint64_t gps_sent = 0;
  uint64_t ground_truth_sent = 0;
  uint64_t heartbeats_sent = 0;
  uint64_t send_errors = 0;  // Messages not sent: no connection, or PX4 not reading (backlog).
};

// PX4's latest actuator outputs as sitlnet applies them.
struct Px4Command {
  RotorSpeeds rotor_speeds_rad_s{};  // u * max rotor speed when armed, else 0.
  bool armed = false;
  uint64_t time_usec = 0;  // PX4's clock when it sent them: the HIL_SENSOR time they answer.
  bool lockstep = false;   // PX4 runs its lock-step scheduler (flags bit 0).
};

class Px4SimulatorLink {
 public:
  // Listens on address:port (TCP, IP_FREEBIND: the robot's ctl0 may not exist yet). Throws Error
  // "<what>: listen TCP a.b.c.d:port: <strerror>". `max_rotor_speed_rad_s`: the airframe's.
  Px4SimulatorLink(Ipv4 address, uint16_t port, double max_rotor_speed_rad_s,
                   const std::string& what);
  ~Px4SimulatorLink();
  Px4SimulatorLink(const Px4SimulatorLink&) = delete;
  Px4SimulatorLink& operator=(const Px4SimulatorLink&) = delete;

  enum class Event {
    kNone,
    kConnected,    // PX4 connected; it gets sensors from the next Send on.
    kReconnected,  // A new connection replaced the previous one (PX4 restarted): reset the robot.
  };
  // Accepts a waiting connection (the newest wins), reads everything that has arrived and
  // takes its messages. Returns what happened to the connection.
  Event Poll();
  // Poll's two halves, for a caller that knows which fd is readable (one system call each):
  // Accept takes waiting connections, Read what arrived on the connection.
  Event Accept();
  void Read();

  bool connected() const { return connection_fd_ >= 0; }
  // The latest command; all motors 0, disarmed before the first and after a disconnection.
  const Px4Command& command() const { return command_; }
  // True once a HIL_ACTUATOR_CONTROLS answers the last HIL_SENSOR sent (same time_usec).
  bool answered_last_sensor() const;
  // A lock-step driver should wait for PX4's answer: PX4 answered on this connection before,
  // in lock-step (its controls' flag), and the last HIL_SENSOR is not answered yet. As PX4's
  // Gazebo interface does, nothing is awaited before PX4's first controls (PX4 boots on the
  // first sensor messages without answering them). A connection in lock-step that closed (PX4
  // died) is awaited too, until PX4 connects again: the driver's silent-autopilot policy applies.
  bool awaiting_answer() const;

  // Sends one HIL_SENSOR (and HIL_GPS if `gps`, HIL_STATE_QUATERNION if `ground_truth`, both may
  // be null) stamped as given by the caller, and a HEARTBEAT when one is due (every second of
  // the messages' time). Without a connection nothing is sent (send_errors counts it).
  void Send(const mavlink::HilSensor& sensor, const mavlink::HilGps* gps,
            const mavlink::HilStateQuaternion* ground_truth);

  // The port listened on (the kernel's choice when constructed with port 0).
  uint16_t port() const;
  int listen_fd() const { return listen_fd_; }
  int connection_fd() const { return connection_fd_; }  // -1 without a connection
  const Px4LinkCounters& counters() const;

 private:
  void Disconnect();
  void Take(const mavlink::ReceivedFrame& frame);
  void Flush();
  template <typename Message>
  void Append(const Message& message);

  std::string what_;
  double max_rotor_speed_rad_s_;
  int listen_fd_ = -1;
  int connection_fd_ = -1;
  mavlink::FrameParser parser_;
  mavlink::ParserCounters parser_before_;  // Sum over closed connections.
  mutable Px4LinkCounters counters_;
  Px4Command command_;
  uint64_t last_sensor_usec_ = 0;
  bool sensor_sent_ = false;
  bool controls_since_connect_ = false;
  bool lost_in_lockstep_ = false;  // The last connection closed while in lock-step.
  uint64_t next_heartbeat_usec_ = 0;
  uint8_t sequence_ = 0;
  std::vector<uint8_t> outgoing_;  // Not yet accepted by the kernel.
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_PX4_SIMULATOR_LINK_H_

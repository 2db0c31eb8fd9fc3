// sitlnet gcs_link: joins the MAVLink of a ground station robot to a GCS on the host, both ways,
// without a route between any namespace and the host (docs/autopilots.md, "Ground stations").
// One socket lives in the ground station's namespace (UDP port 14550, where the vehicles send
// their MAVLink); the others live in the host's namespace, one per GCS endpoint. A thread moves
// datagrams between them. Nothing here is fatal once the relay runs: a GCS that is absent,
// starts late, restarts or sends first costs datagrams, which are counted.
#ifndef SITLNET_GCS_LINK_GCS_LINK_H_
#define SITLNET_GCS_LINK_GCS_LINK_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"

namespace sitlnet::gcs {

//--------------------------------- Endpoints --------------------------------

// QGroundControl's and MAVProxy's UDP port, and the port the vehicles send to on the station.
inline constexpr uint16_t kGcsUdpPort = 14550;

// Where the relay meets a GCS on the host.
struct GcsEndpoint {
  enum class Kind {
    kUdp,        // Datagrams to HOST:PORT from an unconnected socket; answers from any sender.
    kTcpListen,  // A TCP server on 127.0.0.1:PORT (ArduPilot SITL's convention); any clients.
  };
  Kind kind = Kind::kUdp;
  std::string host = "127.0.0.1";  // kUdp only: an IPv4 address.
  uint16_t port = kGcsUdpPort;
  std::string text;  // As written: "udp:127.0.0.1:14550".
};

// Parses "udp:HOST:PORT" (HOST an IPv4 address) or "tcp-listen:PORT". Throws Error naming the
// text and the form expected.
GcsEndpoint ParseGcsEndpoint(const std::string& text);

// udp:127.0.0.1:14550, where QGroundControl listens by default.
GcsEndpoint DefaultGcsEndpoint();

//--------------------------------- The relay --------------------------------

struct GcsRelayOptions {
  std::string station_netns;            // The ground station's namespace, `ip netns` name.
  uint16_t station_port = kGcsUdpPort;  // Bound there on every address.
  std::vector<GcsEndpoint> endpoints;   // At least one.
  std::string tlog_path;                // gcs.tlog (tlog_writer.h); empty: none.
};

// What the GCS heard of one vehicle (a MAVLink system id), from the frames' headers and its
// autopilot's HEARTBEATs.
struct VehicleCounters {
  uint8_t system_id = 0;
  // The sender of the first datagram that carried this system id: the vehicle's radio address,
  // which names its robot (runner/gcs_relay_stage.h).
  Ipv4 address;
  uint64_t messages = 0;  // Frames of this system id from the radio.
  // Frames missing by the sequence numbers, per component (each counts 0..255 and wraps): the
  // MAVLink loss the GCS sees over the radio, and frames the vehicle never sent.
  uint64_t sequence_gaps = 0;
  // The latest HEARTBEAT of an autopilot (not of a GCS or a component without an autopilot).
  bool heartbeat_seen = false;
  uint8_t type = 0;       // MAV_TYPE
  uint8_t autopilot = 0;  // MAV_AUTOPILOT
  uint8_t base_mode = 0;  // MAV_MODE_FLAG bits
  uint32_t custom_mode = 0;
  bool armed = false;  // MAV_MODE_FLAG_SAFETY_ARMED
};

// What the relay moved and dropped. Datagrams, not frames, unless named.
struct GcsRelayCounters {
  uint64_t from_vehicles = 0;      // Reached the station's port from the radio.
  uint64_t vehicle_addresses = 0;  // Distinct senders heard (IPv4 address and port).
  uint64_t to_gcs = 0;             // Handed to the host's sockets, summed over endpoints.
  // Sent to a GCS that did not take them: an ICMP error came back (no one listens on the port),
  // the socket's buffer was full, or no TCP client was connected.
  uint64_t to_gcs_unreceived = 0;
  uint64_t from_gcs = 0;  // Reached a host socket from a GCS (a TCP read counts one).
  // UDP datagrams of those that held no whole MAVLink frame: dropped, never sent on the radio.
  uint64_t from_gcs_without_frame = 0;
  uint64_t from_gcs_bytes_dropped = 0;  // Bytes from a GCS that began no frame: dropped.
  uint64_t to_vehicles = 0;             // Whole frames of a GCS sent to a vehicle, one per vehicle.
  uint64_t to_vehicles_failed = 0;
  // Frames of a GCS sent to their target system's vehicle only (station_socket.h).
  uint64_t to_vehicles_routed = 0;
  uint64_t gcs_clients = 0;               // TCP clients accepted.
  uint64_t tlog_frames = 0;               // Frames written to gcs.tlog.
  uint64_t tlog_bytes_skipped = 0;        // Bytes of the vehicles' datagrams that began no frame.
  std::vector<VehicleCounters> vehicles;  // By system id, ascending.
};

class GcsRelay {
 public:
  // Binds every socket (the station's from a thread that enters its namespace; the sockets
  // stay there), opens the tlog, and starts the relay's thread. Throws Error naming the socket,
  // the address and the reason (a TCP port in use, a bad namespace).
  explicit GcsRelay(const GcsRelayOptions& options);
  ~GcsRelay();  // Stop().
  GcsRelay(const GcsRelay&) = delete;
  GcsRelay& operator=(const GcsRelay&) = delete;

  // The simulation's time now, stamped on the frames the tlog records from here on, until
  // UseTimebase. Any thread.
  void SetVirtualNow(TimeNs virtual_ns);
  // From now on each frame is stamped with timebase.VirtualOf(the instant the relay read it):
  // realtime pacing, once the run's timebase has begun. A copy is kept. Any thread, once.
  void UseTimebase(const clock::Timebase& timebase);
  // Stops the thread and flushes the tlog (throws Error naming it if it cannot be written).
  // Idempotent.
  void Stop();
  // A copy, consistent at any time; final after Stop().
  GcsRelayCounters counters() const;
  // "udp:127.0.0.1:14550, tcp-listen:5760" for the log.
  std::string Describe() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_GCS_LINK_H_

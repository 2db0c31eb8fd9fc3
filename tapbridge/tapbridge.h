// sitlnet tapbridge: joins the robots' wlan0 TAP devices to a simulated 802.11
// medium. Frames read from a TAP enter the medium stamped with their virtual
// time; deliveries are written to the destination TAPs at the wall instant of
// their virtual time (realtime pacing) or before the next step (lockstep).
// Also writes the medium's on-air view as 802.11 + radiotap pcap.
// Design, pacing, counters and the control socket protocol: docs/tapbridge.md.
#ifndef SITLNET_TAPBRIDGE_TAPBRIDGE_H_
#define SITLNET_TAPBRIDGE_TAPBRIDGE_H_

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "scenario/scenario.h"

namespace sitlnet::proto {
class StationCounters;
}

namespace sitlnet::tapbridge {

//------------------------------ Medium interface -----------------------------
// What the bridge needs from a medium model. mac_phy_sim implements it through
// MakeMacPhySimMedium; MakeRelayMedium is the no-medium floor for benchmarks.

// One frame handed to one station, as decided by the medium.
// A frame handed to a robot: the medium model's own record (mac_phy_sim/mac_phy_sim.h), whatever
// the model (802.11, relay, remote). Stations are robot indices.
using mac::Delivery;

// One transmission on the air as the pcap shows it: the medium model's own record of it
// (mac_phy_sim/mac_phy_sim.h TxRecord: timing, kind, addresses, the frame carried; its
// `receptions` are not kept) and the radio view radiotap adds.
struct AirFrame {
  mac::TxRecord tx;
  bool failed = false;  // Collided or lost at its receiver(s): bad FCS in the pcap.
  int channel_mhz = 0;  // 0: the standard's default channel (5180 or 2412).
  bool band_5ghz = true;
  bool ofdm = true;       // False for 802.11b DSSS/CCK.
  double signal_dbm = 0;  // At the receiver (the addressed one, else the strongest).
  double noise_dbm = -93.97;
};

// Medium counters of one station.
struct MediumCounters {
  uint64_t sent = 0;           // Frames accepted from the station into its queue.
  uint64_t delivered = 0;      // Frames handed to this station as a receiver.
  uint64_t queue_drops = 0;    // Dropped by the station's queue: arrived full, or expired in it.
  uint64_t queue_expired = 0;  // Of queue_drops, waited longer than the queue's maximum delay.
  std::vector<std::pair<std::string, uint64_t>> lost;   // By reason, e.g. "retry_limit".
  std::vector<std::pair<std::string, uint64_t>> other;  // Model details (retries, ACKs sent).
};

// The medium fields of proto::StationCounters (medium.proto): the medium daemon's status and
// the remote medium link both carry counters this way.
void MediumCountersToProto(const MediumCounters& counters, proto::StationCounters* out);
MediumCounters MediumCountersFromProto(const proto::StationCounters& in);

class MediumModel {
 public:
  virtual ~MediumModel() = default;
  // Frame `ethernet` from `station` enters its queue at virtual `at_ns`, which
  // is >= every earlier Submit or AdvanceTo instant.
  virtual void Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) = 0;
  // Runs the medium up to and including `until_ns`, appending deliveries (in
  // time order) and, if `air` is not null, on-air frames.
  virtual void AdvanceTo(TimeNs until_ns, std::vector<Delivery>* deliveries,
                         std::vector<AirFrame>* air) = 0;
  // Instant of the next internal event, nullopt when idle.
  virtual std::optional<TimeNs> NextEventNs() const = 0;
  // Moves a station (ENU metres) effective now.
  virtual void SetPosition(int station, double x_m, double y_m, double z_m) = 0;
  // A disabled (detached) station neither sends nor receives from now on.
  virtual void SetStationEnabled(int station, bool enabled) = 0;
  virtual MediumCounters Counters(int station) const = 0;
  // Largest Ethernet frame the medium accepts (14-byte header + MSDU - 8 LLC/SNAP).
  virtual size_t MaxEthernetFrameBytes() const = 0;
  // Hands every transmission (each station's reception with its cause) and every drop to
  // `sink`, as the model decides them, during AdvanceTo. Set before the first AdvanceTo;
  // a model that records no causes ignores it.
  virtual void SetTraceSink(std::function<void(const mac::TraceEvent&)> /*sink*/) {}
};

// 802.11 simulated medium (mac_phy_sim) configured from the scenario.
std::unique_ptr<MediumModel> MakeMacPhySimMedium(const Scenario& scenario);

// No medium: every frame is delivered at the instant it was submitted, to the
// station owning its destination MAC (or to all others for group addresses).
std::unique_ptr<MediumModel> MakeRelayMedium(const std::vector<MacAddress>& station_macs);

// 802.11 maximum MSDU (IEEE 802.11-2016 9.2.4.7.1: 2304 octets) as an Ethernet
// frame: 14-byte header + 2304 - 8 bytes of LLC/SNAP = 2310 bytes.
inline constexpr size_t kMax80211EthernetFrameBytes = 14 + 2304 - 8;

//------------------------------------- Ports ---------------------------------

// Frames read from one robot's port per wake-up (realtime) or per step (lockstep); the rest wait
// in the port's queue for the next turn, after the other robots': a robot that writes as fast as
// the bridge reads cannot hold the loop (audit finding 16, docs/tapbridge.md). 256 frames in a
// 10 ms step is 25 600 frames/s per robot, about ten times what 802.11a carries at 54 Mbit/s.
inline constexpr size_t kMaxFramesPerRobotPerTurn = 256;

// A robot's end of the medium: the bridge reads what the robot sent from it and writes what the
// medium delivered to the robot into it. TapPort is the robot's wlan0 TAP on this host;
// fleet::RemotePorts holds those of robots on node hosts (docs/protocols.md). One thread.
class Port {
 public:
  virtual ~Port() = default;
  // One frame into `buffer` (cut to its size): its length, 0 when none waits, -errno when the
  // port failed (the bridge then detaches the robot).
  virtual ssize_t Read(std::span<uint8_t> buffer) = 0;
  // One frame to the robot: 0, or -errno when it was not written (counted in write_errors).
  virtual int Write(std::span<const uint8_t> frame) = 0;
  // A descriptor that polls readable while frames wait, for the realtime driver; -1 when there
  // is none, and then only the lockstep driver reads the port.
  virtual int fd() const { return -1; }
  // Frames the robot sent that the port's own queue dropped before the bridge read them (a
  // TAP's tx_dropped); nullopt when unknown.
  virtual std::optional<uint64_t> KernelTxDropped() = 0;
};

//------------------------------------ Bridge ---------------------------------

// Per-robot counters kept by the bridge (medium counters are separate).
struct PortCounters {
  uint64_t frames_read = 0;
  uint64_t bytes_read = 0;
  uint64_t oversize_dropped = 0;        // Above MaxEthernetFrameBytes: dropped, counted.
  uint64_t runt_dropped = 0;            // Shorter than an Ethernet header.
  uint64_t unknown_source_dropped = 0;  // Source MAC is not the robot's (docs/tapbridge.md).
  uint64_t frames_written = 0;
  uint64_t write_errors = 0;       // write() to the TAP failed (e.g. ENOBUFS).
  uint64_t kernel_tx_dropped = 0;  // TAP queue overflow seen by the kernel (tx_dropped).
  bool attached = false;
};

// Delivery lateness: wall instant written minus wall instant due.
struct LatenessStats {
  uint64_t count = 0;
  TimeNs p50_ns = 0;
  TimeNs p99_ns = 0;
  TimeNs max_ns = 0;
};

struct BridgeOptions {
  uint64_t seed = 1;  // Lockstep intra-step offsets.
  // Realtime: wake this long before an event and busy-wait the rest (0: pure
  // timer wakeups). Trades CPU for delivery precision (docs/performance.md).
  TimeNs spin_ns = 0;
  // Writes log lines (one line each, no newline); default: stderr with a prefix.
  std::function<void(const std::string&)> log;
  // Attach only these robots (indices); empty: all.
  std::vector<int> robots;
  // Opens robot `robot`'s port (never null; throws Error saying why it cannot). Empty: the
  // robot's wlan0 TAP in its namespace (TapPort).
  std::function<std::unique_ptr<Port>(int robot)> open_port;
};

class EventLoop;

// Receives every on-air frame (pcap writer, live subscribers).
using AirFrameObserver = std::function<void(const AirFrame&)>;

// Owns the robots' ports and the medium. Use from one thread.
class BridgeCore {
 public:
  BridgeCore(const Scenario& scenario, std::unique_ptr<MediumModel> medium, BridgeOptions options);
  ~BridgeCore();
  BridgeCore(const BridgeCore&) = delete;
  BridgeCore& operator=(const BridgeCore&) = delete;

  // Opens every robot's port (BridgeOptions::open_port; by default its persistent wlan0 TAP in
  // its namespace). Throws Error naming the robot and why on failure (scenario not up).
  void AttachAll();

  void AddAirFrameObserver(AirFrameObserver observer);
  // Receives every delivery as the medium decided it, before it is written
  // to the destination TAP (the run's delivery log, connectivity).
  void AddDeliveryObserver(std::function<void(const Delivery&)> observer);
  // On-air frames are produced (and observers called) only while enabled,
  // so an unobserved medium does not pay for its trace. Default: enabled.
  void SetAirFrameCapture(bool enabled);

  //---- Realtime driver: registers ports and a timerfd on `loop`; virtual time
  //---- follows `timebase` (the run's origin and realtime factor, clock/clock.h).
  void StartRealtime(EventLoop* loop, const clock::Timebase& timebase);
  TimeNs VirtualNowNs() const;
  // Unregisters from the loop (also done by the destructor); the loop may be
  // destroyed afterwards. Virtual time stays where it stopped.
  void StopRealtime();

  //---- Lockstep driver: drains every port, enters the frames during
  //---- (previous until, until_ns] at seeded instants in robot order, runs the
  //---- medium to until_ns and writes every delivery due by then.
  void StepLockstep(TimeNs until_ns);

  // Position update from the coordinator or the control socket.
  void SetPosition(int robot, double x_m, double y_m, double z_m);

  // Robot whose namespace vanished: close its port, disable its station, log.
  void Detach(int robot, const std::string& reason);
  // Tries to attach a detached robot again (its namespace came back); true if
  // attached afterwards.
  bool Reattach(int robot);

  int robot_count() const;
  const Scenario& scenario() const;
  const PortCounters& port_counters(int robot) const;
  MediumCounters medium_counters(int robot) const;
  // Lateness since the last call (realtime only), then reset.
  LatenessStats TakeLateness();
  // Lateness since StartRealtime.
  LatenessStats TotalLateness() const;
  // Refreshes kernel_tx_dropped from the ports (a TAP: its namespace's /proc/net/dev).
  void RefreshKernelCounters();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//------------------------------------ Event loop -----------------------------

// One epoll loop. Callbacks get the epoll event mask.
class EventLoop {
 public:
  EventLoop();
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  void Add(int fd, uint32_t events, std::function<void(uint32_t)> callback);
  void Modify(int fd, uint32_t events);
  void Remove(int fd);
  // Runs after every batch of events (the bridge advances the medium there).
  void SetAfterBatch(std::function<void()> callback);
  // Waits once (timeout_ms -1: forever) and dispatches.
  void RunOnce(int timeout_ms);
  void Run();  // Until Stop().
  void Stop();
  bool stopped() const;
  // Expires when the loop is destroyed: users that may outlive it (BridgeCore)
  // check it before unregistering.
  std::weak_ptr<const void> lifetime() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//------------------------------------ pcap -----------------------------------

// pcap (nanosecond, DLT_IEEE802_11_RADIO = 127) encoding of the on-air view.
// Timestamps are `epoch_offset_ns` + the frame's virtual start instant.
std::string PcapFileHeader();
std::string EncodePcapRecord(const AirFrame& frame, TimeNs epoch_offset_ns);
// The 802.11 MPDU with FCS (no radiotap), as it appears in the record.
std::vector<uint8_t> Encode80211Mpdu(const AirFrame& frame);

//------------------------------------ Daemon ---------------------------------

struct DaemonOptions {
  std::string pcap_path;                   // Empty: no file.
  std::string control_socket;              // Empty: ControlSocketPath(scenario name).
  TimeNs stats_interval_ns = 5 * kNsPerS;  // Lag/counter log period.
  bool use_relay_medium = false;           // Benchmarks: no 802.11 model.
  // SCHED_FIFO priority of the daemon (0: normal scheduling). Deliveries are
  // due to the microsecond; on a loaded host a normal thread waits for a core
  // for milliseconds (docs/performance.md). Refused (no CAP_SYS_NICE): logged.
  int realtime_priority = kDefaultRealtimePriority;
  TimeNs spin_ns = 0;  // BridgeOptions::spin_ns.
  std::function<void(const std::string&)> log;
};

// "/run/sitlnet/<scenario>/medium.sock".
std::string ControlSocketPath(const std::string& scenario_name);

// Runs the medium daemon of a scenario that is up until SIGINT/SIGTERM:
// attaches the TAPs, paces in realtime, serves the control socket, logs lag.
// Returns the process exit status.
int RunMediumDaemon(const Scenario& scenario, const DaemonOptions& options);

//------------------------------ Control client -------------------------------
// Length-prefixed (uint32 little-endian) protobuf messages from
// proto/sitlnet/medium.proto over the Unix stream socket.

class ControlClient {
 public:
  explicit ControlClient(const std::string& socket_path);  // Throws Error.
  // Serialized MediumRequest in, serialized MediumResponse out. Throws Error.
  std::string Call(const std::string& request_bytes);
  // After a subscribe_pcap response, the socket carries a raw pcap stream.
  int fd() const { return fd_.get(); }

 private:
  UniqueFd fd_;
};

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_TAPBRIDGE_H_

// sitlnet network side: the coordinator's network simulators. It owns the robots' TAP ports
// (through tapbridge, which attaches them with nns) and the local or remote 802.11 medium; the
// coordinator steps it and the physics side (physics_side/) on its clock.
#ifndef SITLNET_NETWORK_SIDE_NETWORK_SIDE_H_
#define SITLNET_NETWORK_SIDE_NETWORK_SIDE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/common.h"
#include "coordinator/connector.h"
#include "coordinator/pacer.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "scenario/scenario.h"
#include "sitlnet/medium_link.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::network_side {

using coordinator::IterationContext;
using coordinator::Simulator;

//------------------------- The medium alone (tests, benches) -------------------------

// A frame to submit at a virtual instant.
struct TimedFrame {
  TimeNs at_ns = 0;
  int station = 0;
  std::vector<uint8_t> ethernet_frame;
};

// Produces the frames robots send during [from_ns, to_ns), in submission order.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual void FramesIn(TimeNs from_ns, TimeNs to_ns, std::vector<TimedFrame>* out) = 0;
};

// Every robot broadcasts a `payload_bytes` UDP-like frame every `period_ns`,
// robot i offset by i·period/robots (the DANCERS case study's state
// broadcast; the "200 B at 10 Hz" broadcast scale test of docs/references.md#ns3-tapbridge).
// Payload bytes carry the robot index and sequence number, so every frame is distinct.
class PeriodicBroadcast final : public FrameSource {
 public:
  PeriodicBroadcast(int robots, TimeNs period_ns, int payload_bytes);  // payload_bytes >= 16
  void FramesIn(TimeNs from_ns, TimeNs to_ns, std::vector<TimedFrame>* out) override;

 private:
  int robots_;
  TimeNs period_ns_;
  int payload_bytes_;
};

// Network simulator over the 802.11 medium alone (mac_phy_sim, no TAPs): robot positions
// from START move the stations, frames come from a FrameSource, and the medium advances δ_net by
// δ_net to the iteration's end. Used by the correctness and reproducibility tests and by the
// benchmark.
class MediumSimulator final : public Simulator {
 public:
  // `source` may be null (no traffic); both must outlive the simulator.
  MediumSimulator(const Scenario& scenario, FrameSource* source);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;
  // Every delivery so far, in medium order, if recording is on (default off).
  void set_record(bool record) { record_ = record; }
  const std::vector<mac::Delivery>& deliveries() const { return records_; }
  uint64_t delivery_count() const { return delivery_count_; }
  mac::Medium& medium() { return medium_; }

 private:
  mac::Medium medium_;
  FrameSource* source_;
  TimeNs step_ns_;
  bool record_ = false;
  std::vector<TimedFrame> frames_;
  std::vector<mac::Delivery> deliveries_;
  std::vector<mac::Delivery> records_;
  uint64_t delivery_count_ = 0;
};

//------------------------------ The run's network side ------------------------------

// The network side of `sitlnet run`: a coordinator Simulator over the
// tapbridge (robots' TAPs + the mac_phy_sim medium). Each iteration moves the
// stations to the poses physics reported, then
//  - realtime: runs the bridge's event loop until the wall instant of the
//    iteration's end (deliveries are written at their own wall instants);
//  - lockstep: steps the medium δ_net by δ_net, draining the TAPs first.

class BridgeSimulator final : public Simulator {
 public:
  // `bridge` must be attached and outlive this.
  BridgeSimulator(const Scenario& scenario, tapbridge::BridgeCore* bridge,
                  coordinator::Pacing pacing, double realtime_factor);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  void MoveStations(const proto::coord::Poses& poses);

  tapbridge::BridgeCore& bridge_;
  coordinator::Pacing pacing_;
  clock::Timebase timebase_;  // Begun at the first realtime iteration.
  TimeNs network_step_ns_;
  tapbridge::EventLoop loop_;
  bool started_ = false;
};

//------------------------------ Medium on another host ------------------------------

// The 802.11 medium on another host (`sitlnet run --remote network`,
// `sitlnet medium --connect`; docs/coordinator.md, "A connector on another
// host"). The robots' TAPs stay with their namespaces, in the bridge on the
// coordinator's host; what moves is the medium model (mac_phy_sim), behind
// tapbridge's MediumModel interface:
//  - RemoteMedium (coordinator's host) records the bridge's calls during one
//    network step and, at the step's end, sends them as one START to the
//    network connector and returns what its END carried (a step without new
//    frames that ends before the medium's next event is not sent: its calls
//    go with the next one);
//  - MediumLinkSimulator (the other host) replays them on a real medium.
// The medium sees exactly the calls it would see in-process, so lockstep runs
// are byte-identical either way (tests/integration/remote_run_test.cc).
// Lockstep pacing only: in realtime the bridge asks its medium for the next
// event at every frame, a round trip each.

// The medium link of a run with --remote network (network_side/network_side.h):
// sums over its round trips, for the run's log, summary.json and
// docs/performance.md.
struct MediumLinkStats {
  int64_t round_trips = 0;
  TimeNs round_trip_ns = 0;   // START sent -> END received.
  TimeNs remote_busy_ns = 0;  // The remote medium's own time (End.busy_ns).
  int64_t request_bytes = 0;  // MediumRequest payloads sent.
  int64_t reply_bytes = 0;    // MediumReply payloads received.
  int64_t quiet_steps = 0;    // Network steps that needed no round trip.

  // Means per round trip (0 round trips count as 1), for the log line and summary.json.
  struct Means {
    double round_trip_us = 0, remote_medium_us = 0, transport_us = 0;
    double request_bytes = 0, reply_bytes = 0;
  };
  Means PerRoundTrip() const {
    const double n = static_cast<double>(round_trips > 0 ? round_trips : 1);
    const double us = n * kNsPerUs;
    return {static_cast<double>(round_trip_ns) / us, static_cast<double>(remote_busy_ns) / us,
            static_cast<double>(round_trip_ns - remote_busy_ns) / us,
            static_cast<double>(request_bytes) / n, static_cast<double>(reply_bytes) / n};
  }
};

// What both ends hash in the handshake: the scenario without the settings the
// remote medium does not use (timing.duration_ms, timing.pacing), so
// `sitlnet run --duration 5 --pacing lockstep` meets a plain
// `sitlnet medium FILE --connect`. Seed and radio settings are covered.
uint64_t MediumScenarioHash(const Scenario& scenario);

class RemoteMedium final : public tapbridge::MediumModel {
 public:
  // `connector`: an accepted network connector (AcceptConnectorOfRole). The
  // bridge's lockstep steps end on multiples of the scenario's δ_net: the
  // recorded calls are sent when the bridge advances to such an instant.
  // `answer_timeout_ns`: longest wait for one step's reply.
  RemoteMedium(const Scenario& scenario, std::unique_ptr<coordinator::Connector> connector,
               TimeNs answer_timeout_ns);
  ~RemoteMedium() override;  // Stops the connector if Stop() was not called.

  void Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) override;
  void AdvanceTo(TimeNs until_ns, std::vector<mac::Delivery>* deliveries,
                 std::vector<tapbridge::AirFrame>* air) override;
  // Realtime pacing is refused for a remote medium; the lockstep bridge does
  // not ask.
  std::optional<TimeNs> NextEventNs() const override { return std::nullopt; }
  void SetPosition(int station, double x_m, double y_m, double z_m) override;
  void SetStationEnabled(int station, bool enabled) override;
  // Fetched from the remote when stale (one round trip); after a failure of
  // the link, the last counters received.
  tapbridge::MediumCounters Counters(int station) const override;
  size_t MaxEthernetFrameBytes() const override { return tapbridge::kMax80211EthernetFrameBytes; }

  // Tells the remote connector the run is over (once; never throws).
  void Stop(const std::string& reason);
  const MediumLinkStats& stats() const { return stats_; }
  std::string Describe() const { return connector_->Describe(); }

 private:
  // Sends the recorded calls, waits for the reply (throws Error naming the
  // connector on failure; the link is then dead).
  void Exchange(bool want_counters);
  proto::medium::MediumOp* NewOp() { return request_.add_ops(); }

  std::unique_ptr<coordinator::Connector> connector_;
  TimeNs network_step_ns_;
  TimeNs answer_timeout_ns_;
  int stations_;
  proto::medium::MediumRequest request_;
  proto::medium::MediumReply reply_;
  proto::coord::Start start_;
  proto::coord::End end_;
  std::string payload_;
  uint64_t exchange_ = 0;
  TimeNs last_sent_until_ns_ = 0;
  bool advance_pending_ = false;  // AdvanceTo calls recorded since the last exchange.
  bool submit_pending_ = false;   // Submit calls recorded since the last exchange.
  // The remote medium produces nothing up to this instant (from the last
  // reply; before the first one: nothing known).
  TimeNs remote_quiet_until_ns_ = -1;
  bool healthy_ = true;
  bool stopped_ = false;
  mutable bool counters_stale_ = true;
  mutable std::vector<tapbridge::MediumCounters> counters_;
  MediumLinkStats stats_;
  // Bounds on what the peer may deliver (issue 17, finding 4): copies left of the frames sent
  // (one per other station each), and the longest frame sent.
  int64_t delivery_budget_ = 0;
  size_t longest_submitted_bytes_ = 0;
  // Air frames (pcap records) the peer may report per frame sent: the data frame and its
  // retries (802.11's long retry limit is 7), each with its ACK, RTS and CTS, with room to spare.
  static constexpr int64_t kAirFramesPerFrameSent = 64;
  int64_t air_budget_ = 0;
};

// The other host's side: replays each START's recorded calls on `medium`.
class MediumLinkSimulator final : public Simulator {
 public:
  MediumLinkSimulator(const Scenario& scenario, std::unique_ptr<tapbridge::MediumModel> medium);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    IterationContext& context) override;

 private:
  std::unique_ptr<tapbridge::MediumModel> medium_;
  int stations_;
  TimeNs last_time_ns_;  // The latest time a request may name: the longest run's end, and a step.
  proto::medium::MediumRequest request_;
  proto::medium::MediumReply reply_;
  std::vector<mac::Delivery> deliveries_;
  std::vector<tapbridge::AirFrame> air_;
};

// `sitlnet medium --connect`: where the coordinator listens.
struct RemoteMediumOptions {
  std::string coordinator_endpoint;  // HOST:PORT.
  TimeNs connect_timeout_ns = 60 * kNsPerS;
  std::string secret_file;  // The shared secret (docs/coordinator.md, "Authentication"); or none.
};

// Runs only the 802.11 model of `scenario` (with the run's overrides already applied, as
// runner::ApplyRunOverrides does) as the network connector of a coordinator on another host:
// connects (retrying while nothing listens, up to the timeout), proves with the scenario's hash
// that both loaded the same scenario, serves every network step until the run ends or
// SIGINT/SIGTERM, and returns why it stopped. Throws Error if the coordinator cannot be reached
// or refuses the handshake.
std::string ServeRemoteMedium(const Scenario& scenario, const RemoteMediumOptions& options);

}  // namespace sitlnet::network_side

#endif  // SITLNET_NETWORK_SIDE_NETWORK_SIDE_H_

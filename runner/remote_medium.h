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
#ifndef SITLNET_RUNNER_REMOTE_MEDIUM_H_
#define SITLNET_RUNNER_REMOTE_MEDIUM_H_

#include <memory>
#include <string>
#include <vector>

#include "coordinator/connector.h"
#include "runner/runner.h"
#include "sitlnet/medium_link.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

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
};

// The other host's side: replays each START's recorded calls on `medium`.
class MediumLinkSimulator final : public coordinator::Simulator {
 public:
  MediumLinkSimulator(const Scenario& scenario, std::unique_ptr<tapbridge::MediumModel> medium);
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override;

 private:
  std::unique_ptr<tapbridge::MediumModel> medium_;
  int stations_;
  proto::medium::MediumRequest request_;
  proto::medium::MediumReply reply_;
  std::vector<mac::Delivery> deliveries_;
  std::vector<tapbridge::AirFrame> air_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_REMOTE_MEDIUM_H_

// Network connector over the 802.11 medium alone (mac_phy_sim, no TAPs):
// robot positions from START move the stations, frames come from a
// FrameSource (deterministic test traffic here; the TAPs in tapbridge's
// connector), and the medium advances δ_net by δ_net to the iteration's end.
// Used by the correctness and reproducibility tests and by the benchmark.
#ifndef SITLNET_COORDINATOR_MEDIUM_CONNECTOR_H_
#define SITLNET_COORDINATOR_MEDIUM_CONNECTOR_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "coordinator/connector.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "scenario/scenario.h"

namespace sitlnet::coordinator {

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
// broadcast; the "200 B at 10 Hz" broadcast scale test of docs/references.md#ns3-tapbridge). Payload bytes carry
// the robot index and sequence number, so every frame is distinct.
class PeriodicBroadcast final : public FrameSource {
 public:
  PeriodicBroadcast(int robots, TimeNs period_ns, int payload_bytes);  // payload_bytes >= 16
  void FramesIn(TimeNs from_ns, TimeNs to_ns, std::vector<TimedFrame>* out) override;

 private:
  int robots_;
  TimeNs period_ns_;
  int payload_bytes_;
};

// One delivery as the tests compare them.
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

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_MEDIUM_CONNECTOR_H_

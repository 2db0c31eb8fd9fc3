// What a remote medium (`sitlnet medium --connect`, docs/coordinator.md) answers is input
// (issue 17, finding 4): RemoteMedium checks each reply before anything of it reaches a robot or
// the run's pcap. Here the reply is made up from the fuzzer's bytes (deliveries, air frames,
// shared frames, counters, next event, as MediumReply allows), answered by a connector that
// returns it for the step after two robots sent a frame each; whatever is accepted must be
// within the step, to a station of the scenario, no longer than what was sent, and must encode
// as a well-formed pcap record (the pcap writer's input from the peer).
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/common.h"
#include "coordinator/connector.h"
#include "fuzz/fuzz_inputs.h"
#include "network_side/network_side.h"
#include "tapbridge/tapbridge.h"

namespace {

namespace coord = sitlnet::coordinator;
namespace pm = sitlnet::proto::medium;

// Answers every START with END carrying `reply`, as a connector over the link would.
class ReplyConnector final : public coord::Connector {
 public:
  explicit ReplyConnector(std::string reply)
      : Connector("fuzzed medium", coord::Role::kNetwork), reply_(std::move(reply)) {}
  const sitlnet::proto::coord::Poses& initial_poses() const override { return poses_; }
  void Begin(const sitlnet::proto::coord::Start&, const coord::WaitLimits&) override {}
  bool AwaitCommandsCollected(uint64_t, const coord::WaitLimits&) override { return true; }
  bool Finish(uint64_t iteration, sitlnet::proto::coord::End* end,
              const coord::WaitLimits&) override {
    end->set_iteration(iteration);
    end->set_payload(reply_);
    return true;
  }
  void Stop(const std::string&) override {}

 private:
  std::string reply_;
  sitlnet::proto::coord::Poses poses_;
};

const sitlnet::Scenario& ThreeRobots() {
  static const sitlnet::Scenario scenario = sitlnet::fuzz::ThreeRobotScenario("fzr");
  return scenario;
}

// Times near the step, or anything.
int64_t Time(FuzzedDataProvider& in, int64_t step_ns) {
  return in.ConsumeBool() ? in.ConsumeIntegralInRange<int64_t>(-step_ns, 2 * step_ns)
                          : in.ConsumeIntegral<int64_t>();
}

double Number(FuzzedDataProvider& in) { return sitlnet::fuzz::OddOrInRange(in, -200, 100); }

std::string Reply(FuzzedDataProvider& in, int64_t step_ns) {
  pm::MediumReply reply;
  const int frames = in.ConsumeIntegralInRange(0, 3);
  for (int i = 0; i < frames; ++i) reply.add_frames(in.ConsumeRandomLengthString(200));
  const int deliveries = in.ConsumeIntegralInRange(0, 6);
  for (int i = 0; i < deliveries; ++i) {
    pm::Delivery* d = reply.add_deliveries();
    d->set_station(in.ConsumeIntegralInRange(-1, 4));
    d->set_source(in.ConsumeIntegralInRange(-1, 4));
    d->set_time_ns(Time(in, step_ns));
    if (in.ConsumeBool()) d->set_frame(in.ConsumeRandomLengthString(200));
    d->set_frame_index(in.ConsumeIntegralInRange(-1, 4));
    d->set_rx_power_dbm(Number(in));
    d->set_sinr_db(Number(in));
  }
  const int air = in.ConsumeIntegralInRange(0, 6);
  for (int i = 0; i < air; ++i) {
    pm::AirFrame* f = reply.add_air();
    f->set_start_ns(Time(in, step_ns));
    f->set_duration_ns(in.ConsumeBool() ? in.ConsumeIntegralInRange<int64_t>(0, step_ns)
                                        : in.ConsumeIntegral<int64_t>());
    f->set_transmitter(in.ConsumeIntegralInRange(-1, 4));
    f->set_kind(in.ConsumeIntegralInRange(-1, 6));
    f->set_retry(in.ConsumeBool());
    f->set_failed(in.ConsumeBool());
    f->set_rate_mbps(in.ConsumeBool() ? in.ConsumeFloatingPointInRange<double>(0, 60) : Number(in));
    f->set_channel_mhz(in.ConsumeIntegral<int32_t>());
    f->set_band_5ghz(in.ConsumeBool());
    f->set_ofdm(in.ConsumeBool());
    f->set_signal_dbm(Number(in));
    f->set_noise_dbm(Number(in));
    f->set_duration_field_us(in.ConsumeIntegral<uint32_t>());
    f->set_sequence(in.ConsumeIntegral<uint32_t>());
    f->set_receiver(in.ConsumeBytesAsString(in.ConsumeIntegralInRange(0, 8)));
    f->set_sender(in.ConsumeBytesAsString(in.ConsumeIntegralInRange(0, 8)));
    f->set_frame_index(in.ConsumeIntegralInRange(-1, 4));
  }
  reply.set_idle(in.ConsumeBool());
  reply.set_next_event_ns(Time(in, step_ns));
  const int counters = in.ConsumeIntegralInRange(0, 4);
  for (int i = 0; i < counters; ++i) reply.add_counters()->set_sent(in.ConsumeIntegral<uint64_t>());
  std::string bytes;
  reply.SerializeToString(&bytes);
  // Or the bytes as they come: a reply that is not a MediumReply at all.
  return in.ConsumeBool() ? bytes : in.ConsumeRemainingBytesAsString();
}

using sitlnet::fuzz::Le32;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const sitlnet::Scenario& scenario = ThreeRobots();
  const int64_t step_ns = scenario.network_step_ns;
  FuzzedDataProvider in(data, size);
  const bool want_counters = in.ConsumeBool();
  sitlnet::network_side::RemoteMedium medium(
      scenario, std::make_unique<ReplyConnector>(Reply(in, step_ns)), sitlnet::kNsPerS);
  // a sends 100 bytes to b, b a 60-byte broadcast: the longest frame sent is 114 bytes.
  std::vector<uint8_t> unicast(114, 0x55), broadcast(74, 0x66);
  std::copy(scenario.robots[1].wlan_mac.bytes.begin(), scenario.robots[1].wlan_mac.bytes.end(),
            unicast.begin());
  std::copy(scenario.robots[0].wlan_mac.bytes.begin(), scenario.robots[0].wlan_mac.bytes.end(),
            unicast.begin() + 6);
  std::fill(broadcast.begin(), broadcast.begin() + 6, 0xff);
  std::copy(scenario.robots[1].wlan_mac.bytes.begin(), scenario.robots[1].wlan_mac.bytes.end(),
            broadcast.begin() + 6);
  std::vector<sitlnet::mac::Delivery> deliveries;
  std::vector<sitlnet::tapbridge::AirFrame> air;
  try {
    medium.Submit(0, 100, unicast);
    medium.Submit(1, 200, broadcast);
    if (want_counters) {
      medium.Counters(0);
    } else {
      medium.AdvanceTo(step_ns, &deliveries, &air);
    }
  } catch (const sitlnet::Error&) {
    return 0;  // Refused: the run ends naming the medium.
  }
  for (const sitlnet::mac::Delivery& d : deliveries) {
    if (d.station < 0 || d.station >= 3) __builtin_trap();
    if (d.delivery_ns < 0 || d.delivery_ns > step_ns) __builtin_trap();
    if (d.ethernet_frame.size() > unicast.size()) __builtin_trap();
    if (!std::isfinite(d.rx_power_dbm) || !std::isfinite(d.sinr_db)) __builtin_trap();
  }
  for (const sitlnet::tapbridge::AirFrame& frame : air) {
    // A run's pcap starts at the wall-clock time virtual time 0 stood for (PcapFanout).
    constexpr int64_t kEpochOffsetNs = 1'700'000'000 * sitlnet::kNsPerS;
    const std::string record = sitlnet::tapbridge::EncodePcapRecord(frame, kEpochOffsetNs);
    // pcap record header (16 bytes: seconds, nanoseconds, captured, original), then exactly
    // `captured` bytes: the stream stays parseable whatever the peer sent.
    if (record.size() < 16 || Le32(record, 8) != record.size() - 16 ||
        Le32(record, 12) != Le32(record, 8) || Le32(record, 4) >= sitlnet::kNsPerS) {
      __builtin_trap();
    }
  }
  return 0;
}

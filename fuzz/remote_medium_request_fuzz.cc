// The other end of the remote link: `sitlnet medium --connect` replays each START's recorded
// calls on its 802.11 model (MediumLinkSimulator). The request comes from the coordinator, which
// proves the shared secret but is still another program on another host: a request must be
// refused in one line (Error) or served, never crash or hang the medium. Requests are made up
// from the fuzzer's bytes: submits (any station, time, frame), advances, positions (NaN and
// infinities too), station switches, and the step's bounds; on the default radio or with every
// channel effect on.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/common.h"
#include "coordinator/connector.h"
#include "fuzz/fuzz_inputs.h"
#include "network_side/network_side.h"
#include "tapbridge/tapbridge.h"

namespace {

namespace pm = sitlnet::proto::medium;

// The default radio, or every channel effect on (positions reach the propagation delay).
const sitlnet::Scenario& ThreeRobots(bool every_effect) {
  static const sitlnet::Scenario plain = sitlnet::fuzz::ThreeRobotScenario("fzq");
  static const sitlnet::Scenario effects = sitlnet::fuzz::ThreeRobotScenario("fzq", true);
  return every_effect ? effects : plain;
}

class NoContext final : public sitlnet::coordinator::IterationContext {
 public:
  void CommandsCollected() override {}
};

// Times near step k, or anything.
int64_t Time(FuzzedDataProvider& in, int64_t step_ns, int k) {
  return in.ConsumeBool() ? k * step_ns + in.ConsumeIntegralInRange<int64_t>(-step_ns, 4 * step_ns)
                          : in.ConsumeIntegral<int64_t>();
}

double Coordinate(FuzzedDataProvider& in) { return sitlnet::fuzz::OddOrInRange(in, -100, 100); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const sitlnet::Scenario& scenario = ThreeRobots(in.ConsumeBool());
  const int64_t step_ns = scenario.network_step_ns;
  sitlnet::network_side::MediumLinkSimulator simulator(
      scenario, sitlnet::tapbridge::MakeMacPhySimMedium(scenario));
  NoContext context;
  const int steps = in.ConsumeIntegralInRange(1, 3);
  for (int k = 0; k < steps; ++k) {
    pm::MediumRequest request;
    const int ops = in.ConsumeIntegralInRange(0, 8);
    for (int i = 0; i < ops; ++i) {
      pm::MediumOp* op = request.add_ops();
      switch (in.ConsumeIntegralInRange(0, 4)) {
        case 0: {
          pm::SubmitOp* submit = op->mutable_submit();
          submit->set_station(in.ConsumeIntegralInRange(-1, 4));
          submit->set_at_ns(Time(in, step_ns, k));
          submit->set_ethernet(in.ConsumeRandomLengthString(3000));
          break;
        }
        case 1:
          op->mutable_advance()->set_until_ns(Time(in, step_ns, k));
          op->mutable_advance()->set_trace_air(in.ConsumeBool());
          break;
        case 2: {
          pm::PositionOp* position = op->mutable_position();
          position->set_station(in.ConsumeIntegralInRange(-1, 4));
          position->set_x_m(Coordinate(in));
          position->set_y_m(Coordinate(in));
          position->set_z_m(Coordinate(in));
          break;
        }
        case 3:
          op->mutable_enable()->set_station(in.ConsumeIntegralInRange(-1, 4));
          op->mutable_enable()->set_enabled(in.ConsumeBool());
          break;
        default:
          break;  // An empty operation.
      }
    }
    request.set_want_counters(in.ConsumeBool());
    sitlnet::proto::coord::Start start;
    start.set_iteration(k);
    start.set_start_ns(k * step_ns);
    start.set_end_ns((k + 1) * step_ns);
    if (in.ConsumeBool()) {
      request.SerializeToString(start.mutable_payload());
    } else {
      start.set_payload(in.ConsumeRandomLengthString(100));  // Not a MediumRequest, maybe.
    }
    sitlnet::proto::coord::End end;
    try {
      simulator.RunIteration(start, &end, context);
    } catch (const sitlnet::Error&) {
      return 0;  // Refused: the medium tells the coordinator and stops.
    }
    pm::MediumReply reply;
    if (!reply.ParseFromString(end.payload())) __builtin_trap();
    for (const pm::Delivery& d : reply.deliveries()) {
      if (d.station() < 0 || d.station() >= 3) __builtin_trap();
    }
  }
  return 0;
}

// The other end of the remote link: `sitlnet medium --connect` replays each START's recorded
// calls on its 802.11 model (MediumLinkSimulator). The request comes from the coordinator, which
// proves the shared secret but is still another program on another host: a request must be
// refused in one line (Error) or served, never crash or hang the medium. Requests are made up
// from the fuzzer's bytes: submits (any station, time, frame), advances, positions (NaN and
// infinities too), station switches, and the step's bounds.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/common.h"
#include "coordinator/connector.h"
#include "network_side/network_side.h"
#include "tapbridge/tapbridge.h"

namespace {

namespace pm = sitlnet::proto::medium;

const sitlnet::Scenario& ThreeRobots() {
  static const sitlnet::Scenario scenario = sitlnet::LoadScenarioText(
      "name: \"fzq\"\n"
      "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
      "robot { name: \"b\" position_m { x: 20 y: 0 z: 1 } }\n"
      "robot { name: \"c\" position_m { x: 0 y: 60 z: 1 } }\n"
      "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: 2000 pacing: "
      "PACING_LOCKSTEP seed: 1 }\n",
      "remote_medium_request_fuzz");
  return scenario;
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

double Coordinate(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
      return NAN;
    case 1:
      return in.ConsumeBool() ? INFINITY : -INFINITY;
    case 2:
      return in.ConsumeFloatingPointInRange<double>(-100, 100);
    default:
      return in.ConsumeFloatingPoint<double>();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const sitlnet::Scenario& scenario = ThreeRobots();
  const int64_t step_ns = scenario.network_step_ns;
  FuzzedDataProvider in(data, size);
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

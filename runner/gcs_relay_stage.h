// The run's GCS relay (gcs_link/): which ground station it serves, the endpoints `--gcs` names,
// and the simulated time it stamps gcs.tlog with (docs/autopilots.md, "Ground stations").
#ifndef SITLNET_RUNNER_GCS_RELAY_STAGE_H_
#define SITLNET_RUNNER_GCS_RELAY_STAGE_H_

#include <memory>
#include <string>
#include <vector>

#include "gcs_link/gcs_link.h"
#include "run_formats/run_formats.h"
#include "runner/iteration_observer.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// The endpoints of `--gcs` texts: none given, the default (udp:127.0.0.1:14550); "none" alone,
// none at all. Throws Error naming a bad text, or "none" beside others.
std::vector<gcs::GcsEndpoint> GcsEndpointsOf(const std::vector<std::string>& texts);

// The ground station the relay serves: the scenario's first ground station robot without an
// image (one with an image runs its own GCS on port 14550); null if there is none.
const RobotPlan* RelayedGroundStation(const Scenario& scenario);

// The relay for `scenario`'s ground station, writing run_dir/gcs.tlog, with a line on stderr
// that begins with `program`; null (nothing started) when there is no such station or
// `endpoints` is empty. Throws Error.
std::unique_ptr<gcs::GcsRelay> StartGcsRelay(const Scenario& scenario,
                                             const std::vector<gcs::GcsEndpoint>& endpoints,
                                             const std::string& run_dir,
                                             const std::string& program = "sitlnet run");

// Stops `relay` (null: nothing) and returns what it did for the report, with lines on stderr
// that begin with `program`; a tlog that could not be written is said there too, never fatal.
std::optional<RunReport::GcsRelayReport> StopGcsRelay(gcs::GcsRelay* relay,
                                                      const std::string& program = "sitlnet run");

// The index of the robot in `scenario` whose wlan0 address is `address` (a vehicle's
// VehicleCounters::address), or -1 when no robot has it.
int RobotOfAddress(const Scenario& scenario, Ipv4 address);

// The relay's clock for gcs.tlog. Realtime pacing: from the first iteration on, the run's
// timebase (begun by then), so a frame is stamped when the relay read it, as the bridge stamps
// frames. Lockstep: each iteration's start, as it begins; the run does not wait for the relay,
// so a frame may be stamped an iteration or more after it crossed the medium.
class GcsRelayClock final : public IterationObserver {
 public:
  // `relay` and `timebase` must outlive this.
  GcsRelayClock(gcs::GcsRelay* relay, const clock::Timebase* timebase, bool lockstep)
      : relay_(*relay), timebase_(*timebase), lockstep_(lockstep) {}
  void IterationBegins(const proto::coord::Start& start) override {
    if (lockstep_) {
      relay_.SetVirtualNow(start.start_ns());
    } else if (!timebase_given_) {
      relay_.UseTimebase(timebase_);
      timebase_given_ = true;
    }
  }
  void IterationEnded(const proto::coord::Start& /*start*/) override {}

 private:
  gcs::GcsRelay& relay_;
  const clock::Timebase& timebase_;
  const bool lockstep_;
  bool timebase_given_ = false;
};

// Tells the live view what the GCS heard of each vehicle (run_formats::LiveSink::Vehicles): at the
// first iteration's end, then at most every kPeriodNs of wall time, a copy of the relay's counters
// (a lock the relay's thread holds for one wake-up at most). The page asks twice a second.
class GcsRelayLive final : public IterationObserver {
 public:
  static constexpr TimeNs kPeriodNs = 200 * kNsPerMs;
  // `scenario`, `relay` and `live` must outlive this.
  GcsRelayLive(const Scenario* scenario, const gcs::GcsRelay* relay, run_formats::LiveSink* live)
      : scenario_(*scenario), relay_(*relay), live_(*live) {}
  void IterationEnded(const proto::coord::Start& start) override;

 private:
  const Scenario& scenario_;
  const gcs::GcsRelay& relay_;
  run_formats::LiveSink& live_;
  TimeNs next_wall_ns_ = 0;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_GCS_RELAY_STAGE_H_

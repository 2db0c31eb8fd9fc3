// The run's GCS relay (gcs_link/): which ground station it serves, the endpoints `--gcs` names,
// and the simulated time it stamps gcs.tlog with (docs/autopilots.md, "Ground stations").
#ifndef SITLNET_RUNNER_GCS_RELAY_STAGE_H_
#define SITLNET_RUNNER_GCS_RELAY_STAGE_H_

#include <memory>
#include <string>
#include <vector>

#include "gcs_link/gcs_link.h"
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

// The relay for `scenario`'s ground station, writing run_dir/gcs.tlog, with a line on stderr;
// null (nothing started) when there is no such station or `endpoints` is empty. Throws Error.
std::unique_ptr<gcs::GcsRelay> StartGcsRelay(const Scenario& scenario,
                                             const std::vector<gcs::GcsEndpoint>& endpoints,
                                             const std::string& run_dir);

// Stops `relay` (null: nothing) and returns what it did for the report, with a line on stderr; a
// tlog that could not be written is said there too, never fatal.
std::optional<RunReport::GcsRelayReport> StopGcsRelay(gcs::GcsRelay* relay);

// Tells the relay the virtual time of each iteration as it begins: the stamp of the frames it
// relays during that iteration.
class GcsRelayClock final : public IterationObserver {
 public:
  explicit GcsRelayClock(gcs::GcsRelay* relay) : relay_(*relay) {}
  void IterationBegins(const proto::coord::Start& start) override {
    relay_.SetVirtualNow(start.start_ns());
  }
  void IterationEnded(const proto::coord::Start& /*start*/) override {}

 private:
  gcs::GcsRelay& relay_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_GCS_RELAY_STAGE_H_

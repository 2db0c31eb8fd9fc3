// Whether a realtime run served an autopilot at the wall instant of each message's virtual time,
// read from the test autopilot's log (test_autopilot --log-replies: "reply N t=T pos=X,Y,Z
// wall_ns=W" per message). Served at once at the start of its 10 ms iteration, a message at phase
// p ms into the iteration would come p ms early: the wall - virtual offsets of late-phase
// messages would lie about 6 ms below those of early-phase ones. The host's delays do not depend
// on the phase, so however busy the host, the two medians stay close when the run holds each
// message to its instant (tests/integration/autopilot_run_test.cc, docs/autopilots.md).
#ifndef SITLNET_TESTS_INTEGRATION_SERVED_ON_TIME_H_
#define SITLNET_TESTS_INTEGRATION_SERVED_ON_TIME_H_

#include <cstddef>
#include <string>

namespace sitlnet::nns::testing {

struct ServedOnTime {
  size_t observations = 0;  // From 0.5 s of virtual time on (start-up over).
  size_t early_phase = 0;   // Of them, at phases under 3 ms of the 10 ms iteration.
  size_t late_phase = 0;    // At phases of 6 ms and over.
  // Median offset (wall - virtual) of the early ones less that of the late ones.
  double phase_gap_ms = 0;
  // The offsets' spread: the median less the 5th percentile, the 95th less the median.
  double below_median_ms = 0;
  double above_median_ms = 0;
  // One line for the test's output.
  std::string Describe(const std::string& robot) const;
};

// The measure of the log `log` (its text).
ServedOnTime MeasureServedOnTime(const std::string& log);

}  // namespace sitlnet::nns::testing

#endif  // SITLNET_TESTS_INTEGRATION_SERVED_ON_TIME_H_

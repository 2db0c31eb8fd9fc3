// sitlnet runner: `sitlnet run`, the main job. Brings a scenario up, starts
// the medium (tapbridge + mac_phy_sim), the physics server, every robot's
// image, and the coordinator; writes the run folder (docs/run.md); tears
// everything down at exit, also on Ctrl-C or error.
#ifndef SITLNET_RUNNER_RUNNER_H_
#define SITLNET_RUNNER_RUNNER_H_

#include <cstdint>
#include <optional>
#include <string>

#include "common/common.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

struct RunOptions {
  // The medium model on another host (runner/remote_medium.h): listen here
  // (`host:port`, `unix:/path`) for its network connector (`sitlnet medium
  // FILE --connect`), waiting at most remote_wait_ns. Lockstep pacing only.
  std::string listen;
  TimeNs remote_wait_ns = 60 * kNsPerS;
  std::string scenario_path;
  std::string out_dir;                           // Empty: runs/<scenario>-<UTC date-time>.
  std::optional<double> duration_s;              // Overrides timing.duration_ms.
  std::optional<bool> lockstep;                  // Overrides timing.pacing.
  std::optional<uint64_t> seed;                  // Overrides timing.seed.
  bool no_shadowing = false;                     // radio.shadowing = false.
  std::string sitlnet_exe;                       // For `sitlnet exec` of the images.
  std::string images_root;                       // Folder of the image manifests.
  TimeNs trajectory_period_ns = 100 * kNsPerMs;  // Sampling of trajectories.csv.
  bool progress = true;                          // Live progress line on stderr.
  // SCHED_FIFO priority of sitlnet's own threads in realtime pacing (0: normal scheduling;
  // refused without CAP_SYS_NICE: a warning, then normal). Images run at normal priority.
  int realtime_priority = 10;
};

// The medium link of a run with --remote network (runner/remote_medium.h):
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

struct RunReport {
  std::string run_dir;
  int exit_code = 0;  // 0 ok, 1 failure (robot failure by policy, error), 130 interrupted.
  bool interrupted = false;
  // Wall-clock phases and CPU, for bench/scale (summary.json "resources").
  TimeNs startup_ns = 0;    // From RunScenario's start to the coordinator's first iteration.
  TimeNs loop_ns = 0;       // The coordinator's iterations.
  TimeNs stop_ns = 0;       // Stopping the robots' images.
  double self_cpu_s = 0;    // user+sys of this process (all threads) at the end of the loop.
  double robots_cpu_s = 0;  // user+sys of the reaped children: the robots' images.
  // Peak RSS (VmHWM) of each running image just before it is stopped, largest
  // and median. Not the children's ru_maxrss: that keeps the forked copy of
  // sitlnet's RSS from before exec.
  int64_t robot_max_rss_kib = 0;
  int64_t robot_median_rss_kib = 0;
  std::optional<MediumLinkStats> medium_link;  // --remote network only.
};

// `scenario` with the overrides of `options` (duration_s, lockstep, seed, no_shadowing) applied
// and validated again; source_path kept. `sitlnet medium --connect` applies the same ones, so that
// both ends of a remote medium hash the same scenario.
Scenario ApplyRunOverrides(const Scenario& scenario, const RunOptions& options);

// `sitlnet medium --connect`: where the coordinator listens and the overrides its run applied.
struct RemoteMediumOptions {
  std::string coordinator_endpoint;  // HOST:PORT.
  std::optional<uint64_t> seed;      // The run's --seed, if given.
  bool no_shadowing = false;         // The run's --no-shadowing.
  TimeNs connect_timeout_ns = 60 * kNsPerS;
};

// Runs only the 802.11 model of `scenario` as the network connector of a coordinator on another
// host: connects (retrying while nothing listens, up to the timeout), proves with the scenario's
// hash that both loaded the same scenario, serves every network step until the run ends or
// SIGINT/SIGTERM, and returns why it stopped. Throws Error if the coordinator cannot be reached
// or refuses the handshake.
std::string ServeRemoteMedium(Scenario scenario, const RemoteMediumOptions& options);

// Runs the scenario to the end of its duration (or until SIGINT/SIGTERM).
// Throws Error for bad input found before anything was created; later
// failures are reported in the run folder and on stderr, with everything
// torn down.
RunReport RunScenario(const RunOptions& options);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUNNER_H_

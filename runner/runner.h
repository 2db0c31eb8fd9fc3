// sitlnet runner: `sitlnet run`, the main job. Brings a scenario up, starts
// the medium (tapbridge + mac_phy_sim), the physics server, every robot's
// image, and the coordinator; writes the run folder (docs/run.md); tears
// everything down at exit, also on Ctrl-C or error.
#ifndef SITLNET_RUNNER_RUNNER_H_
#define SITLNET_RUNNER_RUNNER_H_

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/common.h"
#include "fleet/fleet.h"
#include "gcs_link/gcs_link.h"
#include "network_side/network_side.h"
#include "run_formats/run_formats.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

struct RunOptions {
  // How this program's log lines start: the robots' setup and supervision are shared with
  // `sitlnet node`, whose lines say so.
  std::string program = "sitlnet run";
  // The medium model on another host (network_side/network_side.h): listen here
  // (`host:port`, `unix:/path`) for its network connector (`sitlnet medium
  // FILE --connect`), waiting at most remote_wait_ns. Lockstep pacing only.
  std::string listen;
  bool remote_network = false;  // --remote network: `listen` is for the medium.
  TimeNs remote_wait_ns = 60 * kNsPerS;
  // A scenario with nodes (issue 35): its node hosts (`sitlnet node`) connect to `listen`,
  // each within node_wait_ns; with one_host, every robot runs here and `nodes` is ignored.
  TimeNs node_wait_ns = 120 * kNsPerS;
  bool one_host = false;
  // The shared secret both ends prove (docs/coordinator.md, "Authentication"); required when
  // `listen` is reachable from other hosts (coordinator::IsLocalOnly).
  std::string secret_file;
  std::string scenario_path;
  // The scenario as text, loaded instead of the file at scenario_path, which then only names
  // its source (`sitlnet verify` reruns the recorded scenario under the original's name).
  std::optional<std::string> scenario_text;
  std::string out_dir;                           // Empty: runs/<scenario>-<UTC date-time>.
  std::optional<double> duration_s;              // Overrides timing.duration_ms.
  std::optional<clock::Pacing> pacing;           // Overrides timing.pacing.
  std::optional<uint64_t> seed;                  // Overrides timing.seed.
  bool no_shadowing = false;                     // radio.shadowing = false.
  std::string sitlnet_exe;                       // For `sitlnet exec` of the images.
  std::string images_root;                       // Folder of the image manifests.
  TimeNs trajectory_period_ns = 100 * kNsPerMs;  // Sampling of trajectories.csv.
  bool progress = true;                          // Live progress line on stderr.
  bool record_losses = true;  // losses.csv.gz and links.csv (docs/run.md); mac_phy_sim here only.
  // SCHED_FIFO priority of sitlnet's own threads in realtime pacing (0: normal scheduling;
  // refused without CAP_SYS_NICE: a warning, then normal). Images run at normal priority.
  int realtime_priority = kDefaultRealtimePriority;
  // `--gcs`, as written: where the ground station's MAVLink meets a GCS on the host
  // (runner/gcs_relay_stage.h). Empty: udp:127.0.0.1:14550; {"none"}: no relay.
  std::vector<std::string> gcs;
  // `sitlnet run --view` (may be null; outlives the run): told the poses and each second's
  // links while the run goes, on the run's threads; it never blocks them.
  run_formats::LiveSink* live = nullptr;
};

// A file's identity and last change: what tells a file this run wrote from one it found.
struct FileStamp {
  uint64_t device = 0, inode = 0;
  int64_t modified_ns = 0, changed_ns = 0;  // mtime and ctime, as the file system keeps them
  int64_t bytes = 0;
  bool operator==(const FileStamp&) const = default;
};
// By path relative to the run folder.
using RunFolderFiles = std::map<std::string, FileStamp>;

// Every regular file under `run_dir` (no link followed) with its stamp; empty if the folder does
// not exist.
RunFolderFiles ListRunFolderFiles(const std::string& run_dir);

struct RunReport {
  std::string run_dir;
  // The run folder's files at the run's start (none if it did not exist): those still as they
  // were at the end are an earlier run's, left out of summary.json's "outputs". By their stamp,
  // not by comparing file times with this host's clock: a shared volume stamps with its own.
  RunFolderFiles files_before;
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
  std::optional<network_side::MediumLinkStats> medium_link;  // --remote network only.
  std::vector<fleet::FleetLinkStats> fleet_links;            // A fleet's central only.
  // A fleet's central host in realtime pacing: per node, how late its frames entered the medium
  // and its deliveries were written; empty otherwise.
  struct NodeLateness {
    std::string node;         // Its name in the scenario.
    std::string description;  // "node 'n0' (robots a, c)", for the log.
    tapbridge::LatenessStats late_entries, late_writes;
  };
  std::vector<NodeLateness> fleet_realtime;
  // The GCS relay's endpoints and counters (summary.json "gcs_relay"); nullopt without a relay.
  struct GcsRelayReport {
    std::string endpoints;  // "udp:127.0.0.1:14550".
    gcs::GcsRelayCounters counters;
  };
  std::optional<GcsRelayReport> gcs_relay;
};

// `scenario` with the overrides of `options` (duration_s, pacing, seed, no_shadowing) applied
// and validated again; source_path kept. `sitlnet medium --connect` applies the same ones, so that
// both ends of a remote medium hash the same scenario.
Scenario ApplyRunOverrides(const Scenario& scenario, const RunOptions& options);

// Runs the scenario to the end of its duration (or until SIGINT/SIGTERM).
// Throws Error for bad input found before anything was created; later
// failures are reported in the run folder and on stderr, with everything
// torn down.
RunReport RunScenario(const RunOptions& options);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUNNER_H_

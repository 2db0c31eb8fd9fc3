// sitlnet sweep: one scenario run over a grid of field values and seeds, each point a separate
// `sitlnet run` process, with points.csv and summary.csv (mean, standard deviation, Student's t
// 95 % interval). How-to: docs/sweep.md.
#ifndef SITLNET_SWEEP_SWEEP_H_
#define SITLNET_SWEEP_SWEEP_H_

#include <google/protobuf/struct.pb.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sitlnet/scenario.pb.h"

namespace sitlnet::sweep {

//------------------------------- The grid ------------------------------------

// One `--set FIELD=V1,V2,...`: a scenario field by its path and the values it takes, as written.
struct SweepAxis {
  std::string field_path;           // "radio.rate_mbps", "robot[2].position_m.x".
  std::vector<std::string> values;  // At least one, no repeats.
};

// Parses "FIELD=V1,V2,..." (the text of one --set). Throws Error naming the flag.
SweepAxis ParseSetFlag(std::string_view text);

// Parses "1-20", "3", "1,4,7-9" into ascending distinct seeds. Throws Error naming --seeds.
std::vector<uint64_t> ParseSeedList(std::string_view text);

// One run of the sweep: a combination of the axes' values and a seed.
struct SweepPoint {
  int combination = 0;              // Index of the combination of values, from 0.
  std::vector<std::string> values;  // One per axis, in the axes' order.
  uint64_t seed = 0;
  std::string folder;               // Point folder name under --out (PointFolderName).
};

// Every combination of the axes' values (the first axis varies slowest) times every seed (the
// fastest). No axes: one combination with no values.
std::vector<SweepPoint> ExpandGrid(const std::vector<SweepAxis>& axes,
                                   const std::vector<uint64_t>& seeds);

// "radio.rate_mbps=6,seed=3": each axis's field=value, then the seed; '/' and '%' in a value are
// written %2F and %25, so a name is one folder. Throws Error if longer than a file name allows.
std::string PointFolderName(const std::vector<SweepAxis>& axes,
                            const std::vector<std::string>& values, uint64_t seed);

//------------------------------ Field paths ----------------------------------

// Sets the scalar field at `path` (segments "name" or "name[index]", joined by '.') of `spec`
// to `value`, parsed as the field's type (number, bool true/false, enum value name, string).
// Intermediate singular messages are created; an index must name an existing element. Throws
// Error (why, without the path: the caller names its flag) for an unknown field, a non-scalar,
// an index out of range or a value of the wrong type.
void SetFieldByPath(const std::string& path, const std::string& value, proto::Scenario* spec);

// The pseudo-field of `--set robot_count=N1,N2,...`: a point keeps the scenario's first N robots
// (docs/sweep-reference.md, "Fleet size"). The schema has no field of this name.
inline constexpr char kRobotCountField[] = "robot_count";

// Keeps the first `value` robots of `spec`. Throws Error (why, without the flag) unless `value`
// is a whole number from 1 to the robots listed.
void KeepFirstRobots(const std::string& value, proto::Scenario* spec);

// One axis's value: robot_count by KeepFirstRobots, any other path by SetFieldByPath.
void SetAxisValue(const std::string& field_path, const std::string& value,
                  proto::Scenario* spec);

//------------------------- Runs side by side ---------------------------------

// What keeps runs at once from clashing: job slot `slot` of sweep `sweep_id` (this process's id)
// gets the scenario name "sw<sweep_id % 10000>_<slot>" (at most 10 characters), its ctl subnet
// moved `slot` subnet sizes up from the scenario's, and physics port + slot. The wlan subnet is
// kept (it lives only in the robots' namespaces), so a point's medium.pcap does not depend on its
// slot. Throws Error if the subnet would leave the IPv4 space or slot is past 999.
void IsolateForSlot(int slot, unsigned sweep_id, proto::Scenario* spec);

//------------------------------ Statistics -----------------------------------

// The p-quantile of Student's t distribution with `dof` degrees of freedom (p in (0, 1),
// dof >= 1), by Boost.Math.
double StudentTQuantile(double p, int dof);

// Sample statistics of one metric over one combination's points.
struct SampleSummary {
  int n = 0;
  double mean = 0;
  double standard_deviation = 0;  // Sample (n - 1); NaN for n < 2.
  double ci95_half_width = 0;     // t(0.975, n - 1) * sd / sqrt(n); NaN for n < 2.
};
SampleSummary Summarize(const std::vector<double>& samples);

//------------------------------- Results -------------------------------------

// A run folder's summary.json, parsed; nullopt if absent or not one whole JSON object.
std::optional<google::protobuf::Struct> ReadSummaryJson(const std::string& path);

// A point is finished when its summary.json is complete: whole, not interrupted, no failure.
bool IsFinishedSummary(const google::protobuf::Struct& summary);

// The number at `path` ("metrics.stf.mean", "robots[0].medium.sent") of a summary; nullopt if
// absent, null or not a number (a bool counts as 0/1).
std::optional<double> SummaryMetric(const google::protobuf::Struct& summary,
                                    const std::string& path);

// The metrics points.csv and summary.csv carry when no --metric is given (docs/sweep.md).
std::vector<std::string> DefaultMetrics();

//------------------------------- The sweep -----------------------------------

struct SweepOptions {
  std::string scenario_path;
  std::vector<SweepAxis> axes;
  std::vector<uint64_t> seeds;
  std::vector<std::string> metrics;  // Empty: DefaultMetrics().
  int jobs = 0;                      // At most this many runs at once; 0: DefaultJobs().
  std::string out_dir;
  std::string sitlnet_exe;           // The binary whose `run` each point runs.
  std::vector<std::string> run_args; // More arguments for every `sitlnet run` (--no-losses).
  // A cluster's pod (deploy/kubernetes/sweep-job.yaml): run only the point of this index
  // (ExpandGrid's order, from 0) in job slot 0, unless finished, and write no tables: the other
  // points' pods write to the same folder at once. Exit code 0 also when the run failed (it is
  // recorded; --collect reports it). Throws Error naming --point if out of range.
  std::optional<size_t> only_point;
  // `--collect`: run nothing; tabulate the point folders already in out_dir (what the pods wrote).
  bool collect_only = false;
};

// Runs at once by default: one per CPU this process may use (sched_getaffinity).
int DefaultJobs();

// What a sweep did.
struct SweepReport {
  int points = 0;
  int already_finished = 0;  // Found finished and not run again.
  int ran = 0;
  int failed = 0;            // Of those run.
  bool interrupted = false;  // SIGINT/SIGTERM: the runs were stopped and waited for.
  int not_run = 0;           // --collect: points with no finished or failed run in out_dir.
  int exit_code = 0;         // 0 all finished, 1 a point failed or missing, 130 interrupted.
};

// Validates every combination first (one line naming the --set that is wrong), then runs the
// points not yet finished, at most `jobs` at once, then writes points.csv and summary.csv in
// out_dir. Progress and each failure: one line on stderr. Throws Error on bad input.
SweepReport RunSweep(const SweepOptions& options);

}  // namespace sitlnet::sweep

#endif  // SITLNET_SWEEP_SWEEP_H_

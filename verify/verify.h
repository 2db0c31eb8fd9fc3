// sitlnet verify: checks that a lockstep run reproduces. Reads the run record that every
// `sitlnet run` writes into summary.json (SHA-256 of each output, the scenario as run, seed,
// pacing, sitlnet's version), reruns the scenario into a fresh folder, and compares each output
// as the same, within a documented bound, or different. Two existing run folders can be
// compared without a rerun. How-to: docs/sweep.md, "Check that a run reproduces".
#ifndef SITLNET_VERIFY_VERIFY_H_
#define SITLNET_VERIFY_VERIFY_H_

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "runner/runner.h"

namespace sitlnet::verify {

//------------------------------ The run record --------------------------------

// One output of a run as summary.json's "outputs" records it.
struct RecordedOutput {
  std::string sha256;  // 64 lowercase hex digits.
  int64_t bytes = 0;
};

// The parts of a run folder's summary.json that verify reads.
struct RunRecord {
  std::string run_dir;
  std::string source;         // "source": the scenario file the run was started from.
  std::string pacing;         // "PACING_LOCKSTEP" or "PACING_REALTIME".
  uint64_t seed = 0;
  std::string version;        // "sitlnet_version": a git commit, or "unknown".
  std::string scenario_text;  // "scenario_text": the scenario as run (protobuf text).
  bool interrupted = false;
  std::map<std::string, RecordedOutput> outputs;  // By path relative to run_dir.
};

// Reads <run_dir>/summary.json. Throws Error naming the file when it is missing, not JSON, or
// holds no run record (written by a sitlnet older than the record).
RunRecord ReadRunRecord(const std::string& run_dir);

// Throws Error saying why `record` cannot be checked by a rerun or a comparison: a realtime run
// (its outputs follow the host's timing) or an interrupted one (stopped at a wall instant).
void RefuseUnreproducible(const RunRecord& record);

//--------------------------- Comparing one output -----------------------------

enum class Verdict {
  kSame,          // Byte for byte.
  kWithinBound,   // Not byte for byte, and within the bound documented for it.
  kNotCompared,   // Cannot be reproduced by design (wall-clock measurements, a PX4 run).
  kDiffers,       // Outside any documented allowance: the run did not reproduce.
};

// "same", "within bound", "not compared", "differs".
const char* VerdictName(Verdict verdict);

// One output's verdict and, unless the same, why: the first differing row, frame or byte, the
// distance against its bound, or the reason it is not compared.
struct OutputVerdict {
  std::string path;  // Relative to the run folders.
  Verdict verdict = Verdict::kSame;
  std::string detail;
};

// medium.pcap with the fields the robots' hosts decide set to zero, frame by frame: what their
// kernels draw at random (the IPv4 identification, the IPv4 header checksum, an ephemeral UDP
// port (>= 32768) and the UDP checksum), ArduCopter's logger health bit in MAVLink SYS_STATUS
// and the MAVLink checksum over it, and the frame check sequence over them
// (docs/autopilots-evidence.md, "Reproducibility with the real autopilots"). Everything else is
// kept.
std::string WithoutHostDecidedFields(std::string pcap);

// PX4's documented bound between two lockstep flights of the same scenario, aligned at lift-off:
// each path is where PX4's own estimate steers it, and issue 31 bounds that estimate to 0.3 m of
// the truth, so two paths are at most 2 x 0.3 m apart (docs/autopilots-evidence.md).
inline constexpr double kPx4PathBoundM = 0.6;

// How far apart one robot's paths in two trajectories.csv are, each aligned at its lift-off.
struct PathGap {
  double worst_m = 0;             // Largest 3-D distance between aligned rows.
  double worst_horizontal_m = 0;
  double worst_vertical_m = 0;
  std::optional<double> lift_off_s[2];  // When each left the ground; nullopt: it did not.
  double compared_s = 0;          // Simulated time compared.
};

// Robot `robot`'s rows of the two trajectories.csv texts compared from lift-off (the first row
// 5 cm above its height at 3 s) to the end of the shorter; a robot that lifts off in neither is
// compared from the first row. nullopt: the robot has no rows, or lifts off in one run only.
std::optional<PathGap> ComparePathsFromLiftOff(const std::string& trajectories_a,
                                               const std::string& trajectories_b, int robot);

//--------------------------- Comparing run folders ----------------------------

// Which outputs CompareRunFolders takes.
enum class OutputSet {
  kReference,  // Those `reference` recorded (a rerun may write more: a fleet's robot logs).
  kEither,     // Those either recorded: one that only one run wrote differs.
};

// Each output of `outputs`, first checked against its own record (a file changed since its run
// differs), then compared by the rule for its kind (docs/sweep-reference.md, "What verify
// compares"). Sorted by path.
std::vector<OutputVerdict> CompareRunFolders(const RunRecord& reference, const RunRecord& other,
                                             OutputSet outputs = OutputSet::kEither);

// What `sitlnet verify` found; exit_code 0 when no output differs, 1 otherwise.
struct VerifyReport {
  std::string rerun_dir;  // The rerun's folder; empty when two folders were compared.
  std::vector<OutputVerdict> outputs;
  int exit_code = 0;
};

// Reruns the run in `run_dir` (its recorded scenario, seed and pacing; every robot on this host;
// losses recorded if the run recorded them) with `run_options` (images, program) into
// `rerun_dir` (empty: <run_dir>-verify-<UTC date-time>), then compares. Prints one line per
// output on stdout, progress on stderr. Throws Error for a run it refuses or cannot read.
VerifyReport VerifyByRerun(const std::string& run_dir, const std::string& rerun_dir,
                           runner::RunOptions run_options);

// Compares two existing run folders without a rerun, printing as VerifyByRerun does.
VerifyReport VerifyTwoFolders(const std::string& run_dir_a, const std::string& run_dir_b);

}  // namespace sitlnet::verify

#endif  // SITLNET_VERIFY_VERIFY_H_

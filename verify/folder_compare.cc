// The rule for each kind of output (docs/sweep-reference.md, "What verify compares"). A run folder
// is first held to its own record, so that a file edited after its run is caught even when a
// rerun would reproduce the original.
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cstdio>
#include <set>

#include "sitlnet/scenario.pb.h"
#include "verify/first_difference.h"
#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

// Wall-clock measurements of each iteration (docs/run.md): never the same twice.
bool IsWallClockOutput(const std::string& path) {
  return path == "metrics.csv" || path == "stf.png";
}

// The robots of the run that are PX4 (they connect to its simulator port).
int Px4RobotCount(const proto::Scenario& spec) {
  return static_cast<int>(std::count_if(spec.robot().begin(), spec.robot().end(),
                                        [](const proto::Robot& r) { return r.px4_sim_port() != 0; }));
}

proto::Scenario ParseRecordedScenario(const RunRecord& record) {
  proto::Scenario spec;
  ParseTextProtoOrThrow(record.scenario_text, record.run_dir + "/summary.json scenario_text",
                        &spec);
  return spec;
}

// Empty if `path` of `record` is on disk as recorded; else what is wrong with it.
std::string CheckAgainstRecord(const RunRecord& record, const std::string& path) {
  const std::string full = record.run_dir + "/" + path;
  try {
    if (Sha256HexOfFile(full) == record.outputs.at(path).sha256) return "";
    return "changed since its run: " + full + " is not what summary.json recorded";
  } catch (const Error&) {
    return "missing: " + full + " was written by its run and is gone";
  }
}

OutputVerdict ComparePx4Trajectories(const RunRecord& a, const RunRecord& b, int robots) {
  const std::string path = "trajectories.csv";
  const std::string text_a = ReadFileOrThrow(a.run_dir + "/" + path, "trajectories");
  const std::string text_b = ReadFileOrThrow(b.run_dir + "/" + path, "trajectories");
  double worst_m = 0;
  int worst_robot = 0;
  for (int robot = 0; robot < robots; ++robot) {
    const std::optional<PathGap> gap = ComparePathsFromLiftOff(text_a, text_b, robot);
    if (!gap) {
      return {path, Verdict::kDiffers,
              "robot " + std::to_string(robot) + " lifts off in one run only, or has no rows"};
    }
    if (gap->worst_m > worst_m) worst_m = gap->worst_m, worst_robot = robot;
  }
  char detail[256];
  std::snprintf(detail, sizeof detail,
                "a run with PX4: paths at most %.3f m apart (robot %d), aligned at lift-off; "
                "bound %.1f m (docs/autopilots-evidence.md)",
                worst_m, worst_robot, kPx4PathBoundM);
  return {path, worst_m <= kPx4PathBoundM ? Verdict::kWithinBound : Verdict::kDiffers, detail};
}

OutputVerdict CompareOutput(const RunRecord& a, const RunRecord& b, const std::string& path,
                            int robots, bool px4_run) {
  const bool in_a = a.outputs.count(path) > 0, in_b = b.outputs.count(path) > 0;
  if (!in_a || !in_b) {
    return {path, Verdict::kDiffers, "written by " + (in_a ? a : b).run_dir + " only"};
  }
  for (const RunRecord* record : {&a, &b}) {
    const std::string problem = CheckAgainstRecord(*record, path);
    if (!problem.empty()) return {path, Verdict::kDiffers, problem};
  }
  if (IsWallClockOutput(path)) {
    return {path, Verdict::kNotCompared,
            "wall-clock timings of each iteration: never the same twice (docs/run.md)"};
  }
  if (a.outputs.at(path).sha256 == b.outputs.at(path).sha256) return {path, Verdict::kSame, ""};
  if (px4_run && path == "trajectories.csv") return ComparePx4Trajectories(a, b, robots);
  if (px4_run) {
    return {path, Verdict::kNotCompared,
            "a run with PX4: its threads make runs differ, and no bound is documented for this "
            "file (docs/autopilots-evidence.md)"};
  }
  const std::string bytes_a = ReadFileOrThrow(a.run_dir + "/" + path, "output");
  const std::string bytes_b = ReadFileOrThrow(b.run_dir + "/" + path, "output");
  if (path == "medium.pcap") {
    const std::string masked_a = WithoutHostDecidedFields(bytes_a);
    const std::string masked_b = WithoutHostDecidedFields(bytes_b);
    if (masked_a == masked_b) {
      return {path, Verdict::kWithinBound,
              "differs only in fields the robots' kernels draw at random (IPv4 id, ephemeral "
              "UDP ports, checksums, FCS; docs/autopilots-evidence.md)"};
    }
    return {path, Verdict::kDiffers,
            FirstDifference(path, masked_a, masked_b) + " (with the kernels' random fields masked)"};
  }
  return {path, Verdict::kDiffers, FirstDifference(path, bytes_a, bytes_b)};
}

}  // namespace

const char* VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kSame: return "same";
    case Verdict::kWithinBound: return "within bound";
    case Verdict::kNotCompared: return "not compared";
    case Verdict::kDiffers: return "differs";
  }
  return "?";
}

std::vector<OutputVerdict> CompareRunFolders(const RunRecord& reference, const RunRecord& other,
                                             OutputSet outputs) {
  const proto::Scenario spec = ParseRecordedScenario(reference);
  const int robots = spec.robot_size();
  const bool px4_run = Px4RobotCount(spec) > 0;
  std::set<std::string> paths;
  for (const auto& [path, output] : reference.outputs) paths.insert(path);
  if (outputs == OutputSet::kEither) {
    for (const auto& [path, output] : other.outputs) paths.insert(path);
  }
  std::vector<OutputVerdict> verdicts;
  for (const std::string& path : paths) {
    verdicts.push_back(CompareOutput(reference, other, path, robots, px4_run));
  }
  return verdicts;
}

}  // namespace sitlnet::verify

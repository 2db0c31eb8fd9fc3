// `sitlnet sweep`'s steps: check every combination, find what is finished, run the rest, tabulate.
#include <google/protobuf/text_format.h>
#include <sched.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <fstream>

#include "common/common.h"
#include "scenario/scenario.h"
#include "sweep/point_runs.h"
#include "sweep/results_csv.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// Fields the sweep itself sets for every point: sweeping them would be overwritten.
void RefuseOwnFields(const SweepAxis& axis) {
  for (const char* own : {"name", "timing.seed"}) {
    if (axis.field_path == own) {
      throw Error(std::string("--set ") + own + ": set by the sweep itself (" +
                  (axis.field_path == "name" ? "a name per job slot" : "use --seeds") + ")");
    }
  }
}

// The scenario of a point's combination: the file's, with the axes' values set. robot_count
// goes first, whatever the order of the flags: a --set robot[5]... then names a robot the point
// has, or is refused, instead of being set and silently dropped.
proto::Scenario CombinationSpec(const proto::Scenario& base, const std::vector<SweepAxis>& axes,
                                const std::vector<std::string>& values) {
  proto::Scenario spec = base;
  for (const bool fleet_size : {true, false}) {
    for (size_t a = 0; a < axes.size(); ++a) {
      if ((axes[a].field_path == kRobotCountField) != fleet_size) continue;
      try {
        SetAxisValue(axes[a].field_path, values[a], &spec);
      } catch (const Error& error) {
        throw Error("--set " + axes[a].field_path + "=" + values[a] + ": " + error.what());
      }
    }
  }
  return spec;
}

void MakeFolder(const std::string& path) {
  if (mkdir(path.c_str(), 0755) < 0 && errno != EEXIST) {
    throw Error(SystemErrorMessage("create folder \"" + path + "\"", errno));
  }
}

// The last non-empty line of a file, "" if none.
std::string LastLine(const std::string& path) {
  std::ifstream file(path);
  std::string line, last;
  while (std::getline(file, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

}  // namespace

int DefaultJobs() {
  cpu_set_t cpus;
  if (sched_getaffinity(0, sizeof cpus, &cpus) < 0) return 1;
  return std::max(1, CPU_COUNT(&cpus));
}

SweepReport RunSweep(const SweepOptions& options) {
  const Scenario scenario = LoadScenarioFile(options.scenario_path);
  const std::vector<std::string> metrics =
      options.metrics.empty() ? DefaultMetrics() : options.metrics;
  const int jobs = options.jobs > 0 ? options.jobs : DefaultJobs();
  const unsigned sweep_id = static_cast<unsigned>(getpid());
  if (options.seeds.empty()) throw Error("--seeds: no seed");

  // Every combination is checked before anything runs, in the last job slot's addresses too.
  const std::vector<SweepPoint> points = ExpandGrid(options.axes, options.seeds);
  for (const SweepAxis& axis : options.axes) RefuseOwnFields(axis);
  for (size_t p = 0; p < points.size(); p += options.seeds.size()) {
    proto::Scenario spec = CombinationSpec(scenario.spec, options.axes, points[p].values);
    IsolateForSlot(jobs - 1, sweep_id, &spec);
    try {
      ValidateScenarioSpec(spec, options.scenario_path);
    } catch (const Error& error) {
      std::string flags;
      for (size_t a = 0; a < options.axes.size(); ++a) {
        flags += (a ? " " : "") + std::string("--set ") + options.axes[a].field_path + "=" +
                 points[p].values[a];
      }
      throw Error(flags + ": " + error.what());
    }
  }

  if (options.only_point && *options.only_point >= points.size()) {
    throw Error("--point " + std::to_string(*options.only_point) + ": the sweep has " +
                std::to_string(points.size()) + " points (0 to " +
                std::to_string(points.size() - 1) + ")");
  }

  MakeFolder(options.out_dir);
  SweepReport report;
  report.points = static_cast<int>(points.size());
  std::vector<size_t> to_run;
  for (size_t p = 0; p < points.size(); ++p) {
    if (options.only_point && p != *options.only_point) continue;
    const std::string folder = options.out_dir + "/" + points[p].folder;
    const PointState::Status status = ReadPointState(folder, {}).status;
    if (status == PointState::kFinished) {
      ++report.already_finished;
    } else if (options.collect_only) {
      if (status == PointState::kNotRun) ++report.not_run;
      if (status == PointState::kFailed) ++report.failed;
    } else {
      to_run.push_back(p);
    }
  }
  if (options.collect_only) {
    std::fprintf(stderr, "sitlnet sweep: %d points, %d finished, %d failed, %d not run\n",
                 report.points, report.already_finished, report.failed, report.not_run);
  } else if (options.only_point) {
    std::fprintf(stderr, "sitlnet sweep: point %zu of %d (%s): %s\n", *options.only_point,
                 report.points, points[*options.only_point].folder.c_str(),
                 to_run.empty() ? "finished before" : "running");
  } else {
    std::fprintf(stderr, "sitlnet sweep: %d points, %d finished before, %zu to run, %d at once\n",
                 report.points, report.already_finished, to_run.size(), jobs);
  }

  const auto prepare = [&](size_t index, int slot) {
    const SweepPoint& point = points[to_run[index]];
    const std::string folder = options.out_dir + "/" + point.folder;
    MakeFolder(folder);
    std::remove((folder + "/" + kFailureFile).c_str());
    proto::Scenario spec = CombinationSpec(scenario.spec, options.axes, point.values);
    IsolateForSlot(slot, sweep_id, &spec);
    std::string text;
    google::protobuf::TextFormat::PrintToString(spec, &text);
    const std::string input = folder + "/point.textproto";
    WriteWholeFile(input, text);
    PointCommand command;
    command.argv = {options.sitlnet_exe, "run",   input, "--out", folder, "--seed",
                    std::to_string(point.seed), "--no-progress"};
    command.argv.insert(command.argv.end(), options.run_args.begin(), options.run_args.end());
    command.log_path = folder + "/sweep-run.log";
    return command;
  };
  const auto done = [&](const PointExit& exit) {
    const SweepPoint& point = points[to_run[exit.index]];
    const std::string folder = options.out_dir + "/" + point.folder;
    ++report.ran;
    const bool finished = ReadPointState(folder, {}).status == PointState::kFinished;
    std::string outcome = "ok";
    if (exit.stopped && !finished) {
      outcome = "stopped";
    } else if (exit.status != 0 || !finished) {
      ++report.failed;
      const std::string reason = "exit " + std::to_string(exit.status) + ": " +
                                 LastLine(folder + "/sweep-run.log");
      WriteWholeFile(folder + "/" + kFailureFile, reason + "\n");
      outcome = "failed, " + reason;
    }
    std::fprintf(stderr, "sitlnet sweep: [%d/%zu] %s (slot %d): %s\n", report.ran, to_run.size(),
                 point.folder.c_str(), exit.slot, outcome.c_str());
  };
  report.interrupted = RunPoints(to_run.size(), jobs, prepare, done);
  if (options.only_point) {  // A pod: the tables are --collect's, once every pod has ended.
    // A failed run is recorded in its folder (sweep-failure.txt) and --collect reports it; a
    // non-zero exit would only make the Job run the same failing point again.
    report.exit_code = report.interrupted ? 130 : 0;
    return report;
  }

  std::vector<PointState> states;
  for (const SweepPoint& point : points) {
    states.push_back(ReadPointState(options.out_dir + "/" + point.folder, metrics));
  }
  WriteResults(options.out_dir, options.axes, points, states, metrics);
  std::string warning;
  const std::vector<std::string> plots =
      DrawPlots(options.out_dir, options.axes, points,
                SummarizeCombinations(points, states, metrics.size()), metrics, &warning);
  if (!warning.empty()) std::fprintf(stderr, "sitlnet sweep: warning: %s\n", warning.c_str());
  std::fprintf(stderr, "sitlnet sweep: %s/points.csv, %s/summary.csv, %zu plots (%d run, %d failed%s)\n",
               options.out_dir.c_str(), options.out_dir.c_str(), plots.size(), report.ran,
               report.failed,
               report.interrupted ? ", interrupted: rerun the same command to resume" : "");
  report.exit_code = report.interrupted                          ? 130
                     : report.failed > 0 || report.not_run > 0 ? 1
                                                               : 0;
  return report;
}

}  // namespace sitlnet::sweep

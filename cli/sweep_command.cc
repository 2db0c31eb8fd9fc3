// `sitlnet sweep SCENARIO --seeds ... --set FIELD=V1,V2 ...`: many runs of one scenario
// (sweep/sweep.h).
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "runner/runner.h"
#include "sweep/sweep.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kSweepDescription =
    "Runs SCENARIO once per point: each combination of the --set values, times\n"
    "each seed. Every point is a `sitlnet run` of this binary in its own run\n"
    "folder under --out, named by its values (radio.rate_mbps=6,seed=3).\n"
    "At most --jobs points run at once. Each job slot has its own scenario name,\n"
    "subnets and physics port, so runs at once never clash.\n"
    "Rerun the same command to resume: a point whose summary.json is complete\n"
    "is not run again. A failed point is recorded (points.csv, its folder's\n"
    "sweep-failure.txt) and the sweep goes on. Ctrl-C stops every run in order.\n"
    "Writes points.csv (one row per point) and summary.csv (per combination and\n"
    "metric: n, mean, sd, 95 % CI half-width by Student's t; docs/sweep.md).\n"
    "On a cluster each pod runs one point (--point, deploy/kubernetes/sweep-job.yaml)\n"
    "into a shared folder; --collect then writes the tables (docs/sweep.md).";

constexpr const char* kSweepExitCodes =
    "exit codes: 0 every point finished, 1 a point failed (or, with --collect,\n"
    "has no run), 2 usage or a bad\n"
    "scenario or --set value (checked before any run), 130 interrupted.";

struct SweepArguments {
  std::string scenario;
  std::string seeds = "1";
  std::vector<std::string> sets;
  std::vector<std::string> metrics;
  int jobs = 0;
  std::string out;
  bool no_losses = false;
  int point = -1;
  bool collect = false;
};

}  // namespace

Command AddSweepCommand(CLI::App& sitlnet) {
  CLI::App* command =
      sitlnet.add_subcommand("sweep", "run a scenario over seeds and field values, with statistics");
  command->footer(std::string(kSweepDescription) + "\n" + kSweepExitCodes);
  auto arguments = std::make_shared<SweepArguments>();
  command->add_option("SCENARIO", arguments->scenario, "the scenario file")->required();
  command->add_option("--seeds", arguments->seeds, "seeds: N, N-M or a comma list of them (default 1)")
      ->type_name("LIST");
  command
      ->add_option("--set", arguments->sets,
                   "a scalar scenario field by its path and its values, e.g. radio.rate_mbps=6,54 "
                   "or robot[2].position_m.x=0,5; robot_count=1,4 keeps the first N robots "
                   "(repeatable: every combination runs)")
      ->type_name("FIELD=V1,V2,...")
      ->allow_extra_args(false);
  command
      ->add_option("--metric", arguments->metrics,
                   "a number of summary.json by its path, e.g. metrics.stf.mean (repeatable; "
                   "default: docs/sweep.md)")
      ->type_name("PATH")
      ->allow_extra_args(false);
  command
      ->add_option("--jobs", arguments->jobs,
                   "points run at once (default: the CPUs this process may use)")
      ->type_name("N")
      ->check(CLI::Range(1, 999));
  command->add_option("--out", arguments->out, "the sweep folder")->type_name("DIR")->required();
  command->add_flag("--no-losses", arguments->no_losses,
                    "each run without losses.csv.gz and links.csv (sitlnet run --no-losses)");
  CLI::Option* point =
      command
          ->add_option("--point", arguments->point,
                       "run only the point of this index (from 0, in the order of points.csv) "
                       "and write no tables: one pod of a cluster's sweep")
          ->type_name("INDEX")
          ->check(CLI::NonNegativeNumber);
  command
      ->add_flag("--collect", arguments->collect,
                 "run nothing: write the tables of the points already in --out (after the pods)")
      ->excludes(point);
  return {command, [arguments] {
            return ReportErrors("sweep", kExitUsage, [&] {
              sweep::SweepOptions options;
              options.scenario_path = arguments->scenario;
              options.seeds = sweep::ParseSeedList(arguments->seeds);
              for (const std::string& set : arguments->sets) {
                options.axes.push_back(sweep::ParseSetFlag(set));
              }
              options.metrics = arguments->metrics;
              options.jobs = arguments->jobs;
              options.out_dir = arguments->out;
              runner::RunOptions run_options;
              LocateImages(&run_options);
              options.sitlnet_exe = run_options.sitlnet_exe;
              if (arguments->no_losses) options.run_args.push_back("--no-losses");
              if (arguments->point >= 0) options.only_point = static_cast<size_t>(arguments->point);
              options.collect_only = arguments->collect;
              return sweep::RunSweep(options).exit_code;
            });
          }};
}

}  // namespace sitlnet::cli

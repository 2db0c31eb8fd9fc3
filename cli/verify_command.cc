// `sitlnet verify RUN_DIR [RUN_DIR_B]`: does a lockstep run reproduce? (verify/verify.h)
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "runner/runner.h"
#include "verify/verify.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kVerifyDescription =
    "Reruns the lockstep run in RUN_DIR from its record in summary.json (the\n"
    "scenario as run, its seed) into a fresh folder, and compares each output the\n"
    "run recorded. One line per output: same (byte for byte), within bound (a\n"
    "documented allowance: medium.pcap's fields drawn by the robots' kernels, PX4\n"
    "paths within 0.6 m), not compared (wall-clock timings; a PX4 run's other\n"
    "files), or differs (with the first differing row, frame or byte). A file\n"
    "changed since its run differs. A realtime or interrupted run is refused.\n"
    "With RUN_DIR_B, compares the two folders without a rerun (docs/sweep.md).";

constexpr const char* kVerifyExitCodes =
    "exit codes: 0 every output the same or within its bound, 1 an output differs\n"
    "or the rerun failed to start, 2 usage, a refused run or an unreadable record,\n"
    "3 missing privileges (the rerun), 130 interrupted.";

struct VerifyArguments {
  std::vector<std::string> run_dirs;
  std::string out;
  bool progress = true;
};

}  // namespace

Command AddVerifyCommand(CLI::App& sitlnet) {
  CLI::App* command =
      sitlnet.add_subcommand("verify", "check that a lockstep run reproduces, output by output");
  command->footer(std::string(kVerifyDescription) + "\n" + kVerifyExitCodes);
  auto arguments = std::make_shared<VerifyArguments>();
  command->add_option("RUN_DIR", arguments->run_dirs,
                      "the run folder; with a second, the two are compared without a rerun")
      ->required()
      ->expected(1, 2);
  command->add_option("--out", arguments->out,
                      "the rerun's folder (default <RUN_DIR>-verify-<UTC time>)")
      ->type_name("DIR");
  command->add_flag_function(
      "--no-progress", [arguments](int64_t) { arguments->progress = false; },
      "no live progress line of the rerun on stderr");
  return {command, [arguments] {
            return ReportErrors("verify", kExitUsage, [&] {
              if (arguments->run_dirs.size() == 2) {
                return verify::VerifyTwoFolders(arguments->run_dirs[0], arguments->run_dirs[1])
                    .exit_code;
              }
              runner::RunOptions run_options;
              run_options.program = "sitlnet verify";
              run_options.progress = arguments->progress;
              LocateImages(&run_options);
              return verify::VerifyByRerun(arguments->run_dirs[0], arguments->out, run_options)
                  .exit_code;
            });
          }};
}

}  // namespace sitlnet::cli

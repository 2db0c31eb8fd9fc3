// `sitlnet verify RUN_DIR [RUN_DIR_B]`: does a lockstep run reproduce? (verify/verify.h)
#include <memory>
#include <string>

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
    "exit codes: 0 no output differs, 1 an output differs, 2 usage, a refused run,\n"
    "an unreadable record or a rerun that could not start, 3 missing privileges\n"
    "(the rerun), 130 interrupted.";

struct VerifyArguments {
  std::string run_dir;
  std::string run_dir_b;
  std::string out;
  bool progress = true;
};

}  // namespace

Command AddVerifyCommand(CLI::App& sitlnet) {
  CLI::App* command =
      sitlnet.add_subcommand("verify", "check that a lockstep run reproduces, output by output");
  command->footer(std::string(kVerifyDescription) + "\n" + kVerifyExitCodes);
  auto arguments = std::make_shared<VerifyArguments>();
  command->add_option("RUN_DIR", arguments->run_dir, "the run folder")->required();
  command->add_option("RUN_DIR_B", arguments->run_dir_b,
                      "another run folder: the two are compared, without a rerun");
  command->add_option("--out", arguments->out,
                      "the rerun's folder (default <RUN_DIR>-verify-<UTC time>)")
      ->type_name("DIR");
  command->add_flag_function(
      "--no-progress", [arguments](int64_t) { arguments->progress = false; },
      "no live progress line of the rerun on stderr");
  return {command, [arguments] {
            return ReportErrors("verify", kExitUsage, [&] {
              if (!arguments->run_dir_b.empty()) {
                if (!arguments->out.empty()) {
                  throw Error("--out names a rerun's folder; two folders are compared without one");
                }
                return verify::VerifyTwoFolders(arguments->run_dir, arguments->run_dir_b).exit_code;
              }
              runner::RunOptions run_options;
              run_options.program = "sitlnet verify";
              run_options.progress = arguments->progress;
              LocateImages(&run_options);
              return verify::VerifyByRerun(arguments->run_dir, arguments->out, run_options)
                  .exit_code;
            });
          }};
}

}  // namespace sitlnet::cli

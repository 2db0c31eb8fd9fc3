// sitlnet CLI: one CLI11 subcommand per command, each defined in its own file
// (cli/*_command.cc) and dispatched by main.cc. Adding a command = one file
// defining AddXxxCommand + one line in main.cc's list (docs/cli.md).
// Exit codes are documented in docs/cli.md, generated from --help.
#ifndef SITLNET_CLI_COMMANDS_H_
#define SITLNET_CLI_COMMANDS_H_

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "scenario/scenario.h"

namespace sitlnet::runner {
struct RunOptions;
}  // namespace sitlnet::runner

namespace sitlnet::cli {

// Exit codes shared by every command (exec passes the program's own through).
enum ExitCode {
  kExitOk = 0,
  kExitFailure = 1,     // A system operation failed or was refused (clash, foreign object).
  kExitUsage = 2,       // Bad arguments or a bad scenario file.
  kExitPrivileges = 3,  // Missing CAP_NET_ADMIN / CAP_SYS_ADMIN / /dev/net/tun.
};

// One subcommand: its CLI11 definition (owned by the top-level App), what runs
// it once its arguments are parsed, and the exit code of a usage error.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
  int usage_exit_code = kExitUsage;
};

// Each adds its subcommand, with every option it takes, to `sitlnet`.
Command AddRunCommand(CLI::App& sitlnet);      // cli/run_command.cc (runner)
Command AddUpCommand(CLI::App& sitlnet);       // cli/up_down_command.cc
Command AddExecCommand(CLI::App& sitlnet);     // cli/exec_command.cc
Command AddStatusCommand(CLI::App& sitlnet);   // cli/status_command.cc
Command AddDownCommand(CLI::App& sitlnet);     // cli/up_down_command.cc
Command AddMediumCommand(CLI::App& sitlnet);   // cli/medium_command.cc (tapbridge)
Command AddCaptureCommand(CLI::App& sitlnet);  // cli/capture_command.cc (tapbridge)
Command AddPhysicsCommand(CLI::App& sitlnet);  // cli/physics_command.cc (physics_mujoco)
Command AddViewCommand(CLI::App& sitlnet);     // cli/view_command.cc (view)
Command AddNodeCommand(CLI::App& sitlnet);     // cli/node_command.cc (runner)
Command AddSweepCommand(CLI::App& sitlnet);    // cli/sweep_command.cc (sweep)
Command AddVerifyCommand(CLI::App& sitlnet);   // cli/verify_command.cc (verify)

// This binary and the folder of the image manifests ($SITLNET_IMAGES, else the source tree's
// robot_images/), for the images `run` and `node` start (cli/run_command.cc).
void LocateImages(runner::RunOptions* options);

// A scenario file, or the name of a scenario that is up (its state file names
// the file). Throws Error.
Scenario LoadByFileOrName(const std::string& what);

// Runs `body`; an exception becomes one line "sitlnet <command>: <what>" on
// stderr and an exit code: PrivilegeError -> kExitPrivileges, other errors ->
// `error_code`.
int ReportErrors(const char* command, int error_code, const std::function<int()>& body);

}  // namespace sitlnet::cli

#endif  // SITLNET_CLI_COMMANDS_H_

// sitlnet CLI: one function per command, dispatched by main.cc's table.
// Adding a command = one file defining RunXxxCommand + one line in kCommands.
// Exit codes are documented in docs/cli.md.
#ifndef SITLNET_CLI_COMMANDS_H_
#define SITLNET_CLI_COMMANDS_H_

#include <functional>
#include <string>

#include "scenario/scenario.h"

namespace sitlnet::cli {

// Exit codes shared by every command (exec passes the program's own through).
enum ExitCode {
  kExitOk = 0,
  kExitFailure = 1,     // A system operation failed or was refused (clash, foreign object).
  kExitUsage = 2,       // Bad arguments or a bad scenario file.
  kExitPrivileges = 3,  // Missing CAP_NET_ADMIN / CAP_SYS_ADMIN / /dev/net/tun.
};

// Each command gets argv[0] = its own name and parses the rest itself.
int RunUpCommand(int argc, char** argv);
int RunDownCommand(int argc, char** argv);
int RunExecCommand(int argc, char** argv);
int RunStatusCommand(int argc, char** argv);
int RunMediumCommand(int argc, char** argv);   // cli/medium_command.cc (tapbridge)
int RunCaptureCommand(int argc, char** argv);  // cli/capture_command.cc (tapbridge)
int RunPhysicsCommand(int argc, char** argv);  // cli/physics_command.cc (physics_mujoco)
int RunRunCommand(int argc, char** argv);      // cli/run_command.cc (runner)

// A scenario file, or the name of a scenario that is up (its state file names
// the file). Throws Error.
Scenario LoadByFileOrName(const std::string& what);

// True if any argument before "--" is -h or --help.
bool WantsHelp(int argc, char** argv);

// Runs `body`; an exception becomes one line "sitlnet <command>: <what>" on
// stderr and an exit code: PrivilegeError -> kExitPrivileges, other errors ->
// `error_code`.
int ReportErrors(const char* command, int error_code, const std::function<int()>& body);

}  // namespace sitlnet::cli

#endif  // SITLNET_CLI_COMMANDS_H_

// sitlnet: one CLI over the libraries. main() only dispatches; each command
// lives in its own file (cli/*_command.cc) and documents itself with --help.
#include <cstdio>
#include <cstring>

#include "cli/commands.h"

namespace {

struct Command {
  const char* name;
  int (*run)(int argc, char** argv);
  const char* summary;
};

// One line per command; keep in the order a user meets them.
constexpr Command kCommands[] = {
    {"run", sitlnet::cli::RunRunCommand,
     "fly a scenario: robots, medium, physics, images, outputs"},
    {"up", sitlnet::cli::RunUpCommand, "create the robots of a scenario (namespaces, devices)"},
    {"exec", sitlnet::cli::RunExecCommand, "run a program inside a robot's namespace"},
    {"status", sitlnet::cli::RunStatusCommand, "show robots, devices and processes"},
    {"down", sitlnet::cli::RunDownCommand, "remove everything a scenario created"},
    {"medium", sitlnet::cli::RunMediumCommand, "run the simulated 802.11 medium of a scenario"},
    {"capture", sitlnet::cli::RunCaptureCommand, "stream the medium's 802.11 view as pcap"},
    {"physics", sitlnet::cli::RunPhysicsCommand, "run a scenario's MuJoCo physics in real time"},
};

void PrintUsage(FILE* out) {
  std::fprintf(out,
               "usage: sitlnet COMMAND [ARGS...]   (sitlnet COMMAND --help for details)\n\n"
               "commands:\n");
  for (const Command& command : kCommands) {
    std::fprintf(out, "  %-8s %s\n", command.name, command.summary);
  }
  std::fprintf(out,
               "\nexit codes: 0 ok, 1 failed or refused, 2 usage or bad scenario file,\n"
               "3 missing privileges; exec returns the program's own status (docs/cli.md).\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintUsage(stderr);
    return sitlnet::cli::kExitUsage;
  }
  const char* name = argv[1];
  if (!std::strcmp(name, "--help") || !std::strcmp(name, "-h") || !std::strcmp(name, "help")) {
    PrintUsage(stdout);
    return sitlnet::cli::kExitOk;
  }
  for (const Command& command : kCommands) {
    if (!std::strcmp(name, command.name)) return command.run(argc - 1, argv + 1);
  }
  std::fprintf(stderr, "sitlnet: unknown command \"%s\"\n", name);
  PrintUsage(stderr);
  return sitlnet::cli::kExitUsage;
}

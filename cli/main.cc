// sitlnet: one CLI over the libraries. Arguments are parsed by CLI11 (docs/cli.md
// says why); main() only builds the commands, parses and dispatches. Each
// command lives in its own file (cli/*_command.cc) with its options and help.
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/commands.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kDescription =
    "One executable, one command per task. The commands that create or enter\n"
    "namespaces need root, or CAP_NET_ADMIN + CAP_SYS_ADMIN and read-write\n"
    "/dev/net/tun (in Docker: --cap-add NET_ADMIN --cap-add SYS_ADMIN --device\n"
    "/dev/net/tun --security-opt apparmor=unconfined); without them they print\n"
    "one line naming what is missing and exit with 3. `sitlnet COMMAND --help`\n"
    "prints each command's usage, behaviour and exit codes.";

constexpr const char* kExitCodes =
    "exit codes (every command but exec, whose own are in its help): 0 ok, 1 a\n"
    "system operation failed or was refused (nothing is left half-done), 2 usage\n"
    "error or bad scenario file (file:line:col: ...), 3 missing privileges.\n"
    "Errors are one line on stderr: sitlnet <command>: <what was attempted, on\n"
    "what>: <why>.";

// CLI11's help with the usage line first, as iproute2 prints it ("usage: ..."), and each
// option's description wrapped to 80 columns (CLI11 2.1 leaves it on one line).
class HelpFormatter : public CLI::Formatter {
 public:
  HelpFormatter() {
    label("Usage", "usage");
    column_width(kColumnWidth);
  }

  std::string make_option_desc(const CLI::Option* option) const override {
    return Wrap(CLI::Formatter::make_option_desc(option), kLineWidth - kColumnWidth);
  }

  std::string make_help(const CLI::App* app, std::string name,
                        CLI::AppFormatMode mode) const override {
    if (mode == CLI::AppFormatMode::Sub) return make_expanded(app);
    std::stringstream out;
    std::string usage = make_usage(app, name);
    if (usage.starts_with('\n')) usage.erase(0, 1);
    out << usage;
    out << '\n' << make_description(app);
    out << make_positionals(app) << make_groups(app, mode) << make_subcommands(app, mode);
    out << '\n' << make_footer(app);
    return out.str();
  }

 private:
  static constexpr size_t kColumnWidth = 26;
  static constexpr size_t kLineWidth = 80;

  // Greedy word wrap; CLI11 indents each line after a '\n' to the description column.
  static std::string Wrap(const std::string& text, size_t width) {
    std::istringstream words(text);
    std::string wrapped, word;
    size_t line = 0;
    while (words >> word) {
      if (line > 0 && line + 1 + word.size() > width) {
        wrapped += '\n';
        line = 0;
      } else if (line > 0) {
        wrapped += ' ';
        ++line;
      }
      wrapped += word;
      line += word.size();
    }
    return wrapped;
  }
};

// One line: the library's message, the command, and where to read more.
int ReportUsageError(const CLI::App& sitlnet, const std::vector<Command>& commands,
                     const char* first_arg, const CLI::ParseError& error) {
  const CLI::App* failed = nullptr;
  for (const CLI::App* parsed : sitlnet.get_subcommands()) failed = parsed;
  int code = kExitUsage;
  for (const Command& command : commands) {
    if (failed == nullptr && first_arg != nullptr && command.app->get_name() == first_arg) {
      failed = command.app;
    }
    if (command.app == failed) code = command.usage_exit_code;
  }
  const std::string name = failed ? "sitlnet " + failed->get_name() : "sitlnet";
  std::fprintf(stderr, "%s: %s (%s --help)\n", name.c_str(), error.what(), name.c_str());
  return code;
}

int Main(int argc, char** argv) {
  CLI::App sitlnet(kDescription, "sitlnet");
  sitlnet.formatter(std::make_shared<HelpFormatter>());
  sitlnet.footer(kExitCodes);
  sitlnet.require_subcommand(1);
  // In the order a user meets them.
  const std::vector<Command> commands = {
      AddRunCommand(sitlnet),     AddUpCommand(sitlnet),      AddExecCommand(sitlnet),
      AddStatusCommand(sitlnet),  AddDownCommand(sitlnet),    AddMediumCommand(sitlnet),
      AddCaptureCommand(sitlnet), AddPhysicsCommand(sitlnet), AddViewCommand(sitlnet),
      AddNodeCommand(sitlnet),    AddSweepCommand(sitlnet),   AddVerifyCommand(sitlnet),
  };
  const char* first_arg = argc > 1 ? argv[1] : nullptr;
  if (first_arg != nullptr && !std::strcmp(first_arg, "help")) {  // `sitlnet help`, as ever.
    std::fputs(sitlnet.help().c_str(), stdout);
    return kExitOk;
  }
  if (first_arg != nullptr && first_arg[0] != '-') {
    bool known = false;
    for (const Command& command : commands) known |= command.app->get_name() == first_arg;
    if (!known) {
      std::fprintf(stderr, "sitlnet: unknown command \"%s\" (sitlnet --help)\n", first_arg);
      return kExitUsage;
    }
  }
  try {
    sitlnet.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(sitlnet.help().c_str(), stdout);  // The chosen command's help, if any.
    return kExitOk;
  } catch (const CLI::ParseError& error) {
    return ReportUsageError(sitlnet, commands, first_arg, error);
  }
  for (const Command& command : commands) {
    if (command.app->parsed()) return command.run();
  }
  return kExitUsage;  // Not reached: require_subcommand(1).
}

}  // namespace
}  // namespace sitlnet::cli

int main(int argc, char** argv) { return sitlnet::cli::Main(argc, argv); }

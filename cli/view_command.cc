// `sitlnet view RUN_DIR`: a run folder replayed in a web page (view/view.h).
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "view/view.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kViewDescription =
    "Serves a web page that replays the finished run folder RUN_DIR: the map\n"
    "from above with the obstacles, each robot's position and trail, links\n"
    "coloured by delivery ratio over the last second, and a time slider.\n"
    "A timeline shows the connectivity components, STF and lag over time.\n"
    "Clicking a link lists its frames of that second with the cause of each\n"
    "loss (losses.csv.gz). Prints the page's URL, then serves until Ctrl-C.\n"
    "A sweep's folder (sitlnet sweep --out DIR) shows its summary instead:\n"
    "each metric's mean and 95 % interval against the swept fields, and\n"
    "every point with its status and values.\n"
    "Listens on loopback unless --allow-remote; port 0 takes a free port.\n"
    "The page is built with sitlnet (no network at run time; docs/view.md).";

constexpr const char* kViewExitCodes =
    "exit codes: 0 stopped by Ctrl-C or SIGTERM, 1 the address cannot be bound\n"
    "(in use, not this host's), 2 usage, a non-loopback address without\n"
    "--allow-remote, an incomplete run or sweep folder or one of another version.";

struct ViewArguments {
  std::string run_dir;
  std::string listen = view::kDefaultListen;
  bool allow_remote = false;
};

}  // namespace

Command AddViewCommand(CLI::App& sitlnet) {
  CLI::App* command = sitlnet.add_subcommand("view", "replay a run folder in a web page");
  command->footer(std::string(kViewDescription) + "\n\n" + kViewExitCodes);
  auto arguments = std::make_shared<ViewArguments>();
  command->add_option("RUN_DIR", arguments->run_dir, "the run folder (or a sweep's folder)")->required();
  command
      ->add_option("--listen", arguments->listen,
                   std::string("address and port to serve on (default ") + view::kDefaultListen +
                       ")")
      ->type_name("ADDR:PORT");
  command->add_flag("--allow-remote", arguments->allow_remote,
                    "allow an address other than loopback (anyone who reaches it sees the run)");
  return {command, [arguments] {
            return ReportErrors("view", kExitUsage, [&] {
              view::ReplayOptions options;
              options.run_dir = arguments->run_dir;
              options.listen = view::ParseListenAddress(arguments->listen, arguments->allow_remote);
              options.web_dir = SITLNET_VIEW_WEB_DIR;
              try {
                view::ServeReplay(options, [](const std::string& url) {
                  std::printf("sitlnet view: serving %s\n", url.c_str());
                  std::fflush(stdout);
                });
              } catch (const view::ListenError& error) {
                std::fprintf(stderr, "sitlnet view: %s\n", error.what());
                return static_cast<int>(kExitFailure);
              }
              return static_cast<int>(kExitOk);
            });
          }};
}

}  // namespace sitlnet::cli

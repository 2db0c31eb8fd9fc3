// Options that more than one command takes (cli/options.h).
#include "cli/options.h"

#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace sitlnet::cli {

CLI::Option* AddScenarioFileOrName(CLI::App& command, std::string* scenario) {
  return command
      .add_option("SCENARIO", *scenario, "a scenario file, or the name of one that is up")
      ->required();
}

CLI::Option* AddSeedOption(CLI::App& command, std::optional<uint64_t>* seed) {
  return command.add_option("--seed", *seed, "seed of every random draw (overrides timing.seed)")
      ->type_name("N");
}

CLI::Option* AddNoShadowingOption(CLI::App& command, bool* no_shadowing) {
  return command.add_flag("--no-shadowing", *no_shadowing, "radio shadowing off (radio.shadowing)");
}

CLI::Option* AddSecretFileOption(CLI::App& command, std::string* secret_file) {
  return command
      .add_option("--secret-file", *secret_file,
                  "the shared secret both ends of a link (a remote medium, a node host) prove they "
                  "hold before "
                  "anything else: the same file at both ends, owner-only, 16 to 4096 bytes "
                  "(head -c 32 /dev/urandom > PATH; chmod 600 PATH). Required when the run "
                  "listens on an address other hosts can reach (not loopback, not unix:). It "
                  "does not encrypt: on an untrusted network, add an SSH tunnel "
                  "(docs/coordinator.md, \"Authentication\")")
      ->type_name("PATH");
}

CLI::Option* AddRtPriorityOption(CLI::App& command, int* priority) {
  return command
      .add_option("--rt-priority", *priority,
                  "SCHED_FIFO priority of sitlnet's own threads (0: normal scheduling; without "
                  "CAP_SYS_NICE a warning, then normal)")
      ->type_name("P")
      ->check(CLI::Range(0, 99).description("0..99"))
      ->capture_default_str();
}

CLI::Option* AddGcsOption(CLI::App& command, std::vector<std::string>* gcs) {
  // One value per --gcs, repeatable; the forms are checked by the runner, before anything starts.
  return command
      .add_option("--gcs", *gcs,
                  "where the MAVLink of the scenario's ground station (its first ground_station "
                  "robot without an image) meets a GCS on this host: udp:HOST:PORT (from an "
                  "unconnected socket; answers taken from any sender), tcp-listen:PORT (on "
                  "127.0.0.1; GCSs connect), or none. Repeatable. Default udp:127.0.0.1:14550, "
                  "where QGroundControl listens. Writes gcs.tlog in the --out folder. A fleet's "
                  "relay runs on the node host of the station (docs/autopilots.md, \"Ground "
                  "stations\")")
      ->type_name("udp:HOST:PORT|tcp-listen:PORT|none")
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

CLI::Validator SecondsIn(double min_s, bool min_allowed, double max_s) {
  std::ostringstream rule;
  rule << std::setprecision(12) << min_s << (min_allowed ? " <= " : " < ") << "S <= " << max_s;
  const std::string description = rule.str();
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        const bool above = min_allowed ? value >= min_s : value > min_s;
        if (end != text.c_str() && *end == '\0' && above && value <= max_s) return {};
        return "\"" + text + "\" is not " + description + " seconds";
      },
      description);
}

CLI::Option* AddPeerTimeoutOption(CLI::App& command, const std::string& name,
                                  const std::string& help, TimeNs* timeout_ns, int default_s) {
  constexpr double kMaxSeconds = 86400;  // A day: S x 1e9 fits int64 nanoseconds with room.
  return command
      .add_option_function<double>(
          name,
          [timeout_ns](double seconds) { *timeout_ns = static_cast<TimeNs>(seconds * kNsPerS); },
          help + " (default " + std::to_string(default_s) + ")")
      ->type_name("S")
      ->check(SecondsIn(0, false, kMaxSeconds));
}

}  // namespace sitlnet::cli

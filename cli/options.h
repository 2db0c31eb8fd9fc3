// Options that more than one command takes, each defined once: the same
// spelling, type, bounds and help text wherever it appears.
#ifndef SITLNET_CLI_OPTIONS_H_
#define SITLNET_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet::cli {

// SCENARIO: a scenario file, or the name of a scenario that is up.
CLI::Option* AddScenarioFileOrName(CLI::App& command, std::string* scenario);

// --seed N: overrides timing.seed.
CLI::Option* AddSeedOption(CLI::App& command, std::optional<uint64_t>* seed);

// --no-shadowing: radio.shadowing = false.
CLI::Option* AddNoShadowingOption(CLI::App& command, bool* no_shadowing);

// --secret-file PATH: a link's shared secret (docs/coordinator.md).
CLI::Option* AddSecretFileOption(CLI::App& command, std::string* secret_file);

// --rt-priority P: SCHED_FIFO priority 0..99 of sitlnet's own threads (0: normal).
CLI::Option* AddRtPriorityOption(CLI::App& command, int* priority);

// --gcs udp:HOST:PORT|tcp-listen:PORT|none, repeatable: where the ground station's MAVLink meets
// a GCS on this host (runner/gcs_relay_stage.h checks the forms).
CLI::Option* AddGcsOption(CLI::App& command, std::vector<std::string>* gcs);

// Checks a number of seconds: finite, above `min_s` (or equal to it when `min_allowed`) and
// at most `max_s`; its message says so ("not 0 < S <= 86400 seconds").
CLI::Validator SecondsIn(double min_s, bool min_allowed, double max_s);

// A wait for a remote peer (the medium, a node host), in seconds: 0 < S <= 86400 (S x 1e9 must
// fit the int64 nanoseconds added to the clock), stored as nanoseconds. `default_s` is only what
// the help says: *timeout_ns holds the default.
CLI::Option* AddPeerTimeoutOption(CLI::App& command, const std::string& name,
                                  const std::string& help, TimeNs* timeout_ns, int default_s = 60);

}  // namespace sitlnet::cli

#endif  // SITLNET_CLI_OPTIONS_H_

// How virtual time follows the wall clock (docs/time.md): the one pacing type,
// from the command line (--pacing) through the scenario (Scenario::pacing()) to the coordinator.
#ifndef SITLNET_CLOCK_PACING_H_
#define SITLNET_CLOCK_PACING_H_

#include <optional>
#include <string>
#include <string_view>

namespace sitlnet::clock {

enum class Pacing {
  kRealtime,  // Virtual time follows the wall clock times the realtime factor.
  kLockstep,  // As fast as the host allows, reproducible.
};

// "realtime" or "lockstep": the spelling of --pacing and of the logs.
std::string PacingName(Pacing pacing);

// The pacing called `name` (PacingName's spelling), or nullopt.
std::optional<Pacing> ParsePacing(std::string_view name);

}  // namespace sitlnet::clock

#endif  // SITLNET_CLOCK_PACING_H_

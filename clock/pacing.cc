#include "clock/pacing.h"

namespace sitlnet::clock {

std::string PacingName(Pacing pacing) {
  return pacing == Pacing::kRealtime ? "realtime" : "lockstep";
}

std::optional<Pacing> ParsePacing(std::string_view name) {
  for (Pacing pacing : {Pacing::kRealtime, Pacing::kLockstep}) {
    if (name == PacingName(pacing)) return pacing;
  }
  return std::nullopt;
}

}  // namespace sitlnet::clock

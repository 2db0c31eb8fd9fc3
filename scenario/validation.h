// Validation rules of a parsed scenario and derivation of the per-robot plan.
#ifndef SITLNET_SCENARIO_VALIDATION_H_
#define SITLNET_SCENARIO_VALIDATION_H_

#include "scenario/scenario.h"
#include "scenario/source_locator.h"

namespace sitlnet::scenario_internal {

// Checks every rule of docs/scenario.md on scenario->spec and fills the
// derived fields. Throws Error located with `locator` on the first violation.
void ValidateAndDerive(const SourceLocator& locator, Scenario* scenario);

}  // namespace sitlnet::scenario_internal

#endif  // SITLNET_SCENARIO_VALIDATION_H_

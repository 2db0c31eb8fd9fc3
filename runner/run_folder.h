// The run folder of `sitlnet run` (runner-internal).
#ifndef SITLNET_RUNNER_RUN_FOLDER_H_
#define SITLNET_RUNNER_RUN_FOLDER_H_

#include <string>

#include "scenario/scenario.h"

namespace sitlnet::runner {

// Makes `run_dir` and `run_dir/robots` (and missing parents), or accepts each if it exists as a
// real folder of this process's user (or of the user who ran sudo) that neither group nor
// others can write. Throws Error naming the folder otherwise (a symbolic link, someone else's,
// writable by others).
void MakeRunFolder(const std::string& run_dir);

// The scenario with the command line's overrides, as protobuf text: scenario.textproto's body
// and summary.json's "scenario_text".
std::string EffectiveScenarioText(const Scenario& scenario);

// <run_dir>/scenario.textproto: the scenario with the command line's overrides.
void WriteEffectiveScenario(const Scenario& scenario, const std::string& run_dir);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_FOLDER_H_

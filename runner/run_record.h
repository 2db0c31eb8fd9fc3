// The run record of summary.json (docs/run.md, "The run record"): what `sitlnet verify` needs to
// rerun a run and to check its outputs. Runner-internal.
#ifndef SITLNET_RUNNER_RUN_RECORD_H_
#define SITLNET_RUNNER_RUN_RECORD_H_

#include <string>
#include <vector>

#include "common/common.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// One output of a run: summary.json's "outputs" entry.
struct OutputHash {
  std::string path;    // Relative to the run folder: "robots/a.log".
  std::string sha256;  // 64 lowercase hex digits.
  uint64_t bytes = 0;
};

// The run folder's files this run wrote, each with its SHA-256 and size, sorted by path. Left
// out: summary.json (it holds the record), anything that is not a regular file, and the files
// of `before` (RunFolderFiles at the run's start) not written since: an earlier run's in the same
// folder. Call it once every output is complete. Throws Error naming a file it cannot read.
std::vector<OutputHash> HashOutputs(const std::string& run_dir, const RunFolderFiles& before);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_RECORD_H_

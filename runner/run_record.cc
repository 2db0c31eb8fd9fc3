// Why a walk and not a list of the files each writer made: every writer (the medium's records,
// the physics, the robots' logs, gnuplot, the GCS relay) would have to report its paths, and a
// new output would be left out until someone remembered. The folder itself is the list.
#include "runner/run_record.h"

#include <sys/stat.h>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <vector>

namespace sitlnet::runner {

TimeNs CoarseRealtimeNowNs() {
  timespec now{};
  clock_gettime(CLOCK_REALTIME_COARSE, &now);
  return static_cast<TimeNs>(now.tv_sec) * kNsPerS + now.tv_nsec;
}

std::vector<OutputHash> HashOutputs(const std::string& run_dir, TimeNs since_realtime_ns) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  std::error_code error;
  for (fs::recursive_directory_iterator it(run_dir, error), end; !error && it != end;
       it.increment(error)) {
    if (!it->is_regular_file(error) || it->is_symlink(error)) continue;
    const std::string relative = fs::relative(it->path(), run_dir).string();
    if (relative == "summary.json") continue;
    struct stat info {};
    if (lstat(it->path().c_str(), &info) != 0) continue;
    const TimeNs modified_ns = static_cast<TimeNs>(info.st_mtim.tv_sec) * kNsPerS +
                               info.st_mtim.tv_nsec;
    if (modified_ns < since_realtime_ns) continue;
    paths.push_back(relative);
  }
  if (error) throw Error("list run folder \"" + run_dir + "\" to hash its files: " + error.message());
  std::sort(paths.begin(), paths.end());
  std::vector<OutputHash> outputs;
  for (const std::string& path : paths) {
    const std::string full = run_dir + "/" + path;
    const uintmax_t bytes = fs::file_size(full, error);
    outputs.push_back({path, Sha256HexOfFile(full), error ? 0 : bytes});
  }
  return outputs;
}

}  // namespace sitlnet::runner

// Why a walk and not a list of the files each writer made: every writer (the medium's records,
// the physics, the robots' logs, gnuplot, the GCS relay) would have to report its paths, and a
// new output would be left out until someone remembered. The folder itself is the list.
#include "runner/run_record.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace sitlnet::runner {

namespace {

FileStamp StampOf(const struct stat& info) {
  FileStamp stamp;
  stamp.device = info.st_dev;
  stamp.inode = info.st_ino;
  stamp.modified_ns = static_cast<int64_t>(info.st_mtim.tv_sec) * kNsPerS + info.st_mtim.tv_nsec;
  stamp.changed_ns = static_cast<int64_t>(info.st_ctim.tv_sec) * kNsPerS + info.st_ctim.tv_nsec;
  stamp.bytes = info.st_size;
  return stamp;
}

}  // namespace

RunFolderFiles ListRunFolderFiles(const std::string& run_dir) {
  namespace fs = std::filesystem;
  RunFolderFiles files;
  std::error_code error;
  for (fs::recursive_directory_iterator it(run_dir, error), end; !error && it != end;
       it.increment(error)) {
    // An entry's own checks have their own error code: a dangling link (ENOENT) is skipped, not
    // taken for a failed walk.
    std::error_code entry_error;
    if (it->is_symlink(entry_error) || !it->is_regular_file(entry_error)) continue;
    struct stat info {};
    if (lstat(it->path().c_str(), &info) != 0) continue;
    files[fs::relative(it->path(), run_dir).string()] = StampOf(info);
  }
  return files;  // A folder that cannot be listed (absent) has no earlier files.
}

std::vector<OutputHash> HashOutputs(const std::string& run_dir, const RunFolderFiles& before) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  std::error_code error;
  for (fs::recursive_directory_iterator it(run_dir, error), end; !error && it != end;
       it.increment(error)) {
    std::error_code entry_error;
    if (it->is_symlink(entry_error) || !it->is_regular_file(entry_error)) continue;
    const std::string relative = fs::relative(it->path(), run_dir).string();
    if (relative == "summary.json") continue;
    struct stat info {};
    if (lstat(it->path().c_str(), &info) != 0) continue;
    const auto earlier = before.find(relative);
    if (earlier != before.end() && earlier->second == StampOf(info)) continue;  // not written since
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

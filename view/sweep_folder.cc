#include "view/sweep_folder.h"

#include <sys/stat.h>

#include "common/common.h"
#include "view/json_text.h"
#include "view/replayed_run.h"

namespace sitlnet::view {
namespace {

bool IsFile(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

// The table's text; a missing one names what writes it.
std::string SweepTable(const std::string& dir, const char* name) {
  const std::string path = dir + "/" + name;
  if (!IsFile(path)) {
    throw Error("sweep folder \"" + dir + "\" has no " + name +
                " (sitlnet sweep writes it at its end; after --point runs, --collect does)");
  }
  return ReadText(path);
}

}  // namespace

bool IsSweepFolder(const std::string& dir) {
  return IsFile(dir + "/points.csv") && !IsFile(dir + "/summary.json");
}

std::string SweepJson(const std::string& dir) {
  return "{\"folder\":" + Quote(dir) + ",\"points_csv\":" + Quote(SweepTable(dir, "points.csv")) +
         ",\"summary_csv\":" + Quote(SweepTable(dir, "summary.csv")) + "}";
}

}  // namespace sitlnet::view

// The run folder (docs/run.md, "Run folder"): made by this run, or an existing folder that only
// the run's user can write, never a symbolic link. `sitlnet run` is root; a folder another
// local user owns or can write is one in which that user could plant a link between this check
// and a file's creation, and make root write through it (audit finding 7, docs/security.md).
#include "runner/run_folder.h"

#include <fcntl.h>
#include <google/protobuf/text_format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include "common/common.h"

namespace sitlnet::runner {
namespace {

// Folders above the run folder: made when missing (mode 0755), used as they are otherwise.
void MakeParents(const std::string& path) {
  for (size_t slash = path.find('/', 1); slash != std::string::npos;
       slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    if (mkdir(prefix.c_str(), 0755) != 0 && errno != EEXIST) {
      throw Error(SystemErrorMessage("create run folder \"" + prefix + "\"", errno));
    }
  }
}

// Makes `path` (mode 0755), or accepts it if it exists as a folder of this user that no one
// else can write. Throws Error naming the folder and what is wrong with it.
void MakeOwnedFolder(const std::string& path) {
  if (mkdir(path.c_str(), 0755) == 0) return;
  if (errno != EEXIST) throw Error(SystemErrorMessage("create run folder \"" + path + "\"", errno));
  struct stat info {};
  if (lstat(path.c_str(), &info) != 0) {
    throw Error(SystemErrorMessage("run folder \"" + path + "\"", errno));
  }
  const std::string refused = "run folder \"" + path + "\" ";
  if (S_ISLNK(info.st_mode)) {
    throw Error(refused + "is a symbolic link: give the folder itself (--out)");
  }
  if (!S_ISDIR(info.st_mode)) throw Error(refused + "exists and is not a folder");
  if (!IsInvokingUser(info.st_uid)) {
    throw Error(refused + "belongs to user " + std::to_string(info.st_uid) + ", not to " +
                std::to_string(geteuid()) +
                " who runs sitlnet: another user could replace its files with links; choose "
                "another --out");
  }
  if ((info.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    throw Error(refused +
                "can be written by others (group or world): they could replace its files "
                "with links; chmod go-w it or choose another --out");
  }
}

}  // namespace

void MakeRunFolder(const std::string& run_dir) {
  std::string folder = run_dir;
  // "out/" is "out": with the slash, lstat would follow a link named out.
  while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
  MakeParents(folder);
  MakeOwnedFolder(folder);
  MakeOwnedFolder(folder + "/robots");
}

std::string EffectiveScenarioText(const Scenario& scenario) {
  std::string text;
  google::protobuf::TextFormat::PrintToString(scenario.spec, &text);
  return text;
}

void WriteEffectiveScenario(const Scenario& scenario, const std::string& run_dir) {
  const std::string text = EffectiveScenarioText(scenario);
  LineFile(run_dir + "/scenario.textproto",
           "# Effective scenario of this run (from " + scenario.source_path + ")", 1,
           "effective scenario")
      .AppendRecord(text);
}

}  // namespace sitlnet::runner

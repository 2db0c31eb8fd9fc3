// Containers of a scenario (OCI robot images): registration files in the scenario's state
// directory, so that `down` removes them by name also after `sitlnet run` was killed.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <string_view>

#include "nns/nns_internal.h"
#include "nns/nns.h"

namespace sitlnet::nns {
namespace {

constexpr std::string_view kPrefix = "container.";

std::string ScenarioDir(const std::string& scenario) {
  return std::string(kStateDir) + "/" + scenario;
}

// podman only (docs/containers.md: docker cannot join a named network namespace), by absolute
// path: a registration never makes `down` run another program.
bool IsEngine(const std::string& path) {
  struct stat info {};
  return !path.empty() && path[0] == '/' && path.substr(path.rfind('/') + 1) == "podman" &&
         stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

// The names sitlnet gives containers: "sitlnet-" and a robot namespace's characters.
bool IsContainerName(const std::string& name) {
  if (name.rfind("sitlnet-", 0) != 0 || name.size() > 253) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_' || c == '.';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

ContainerRegistration::ContainerRegistration(const std::string& scenario,
                                             const std::string& engine_exe, const std::string& name)
    : path_(ScenarioDir(scenario) + "/" + std::string(kPrefix) + name) {
  internal::RequireScenarioUp(scenario);
  if (!IsEngine(engine_exe)) {
    throw Error("container \"" + name + "\": engine \"" + engine_exe +
                "\" is not podman given by its absolute path");
  }
  if (!IsContainerName(name)) {
    throw Error("container name \"" + name +
                "\" is not one of sitlnet's (sitlnet-[A-Za-z0-9_.-]+)");
  }
  std::ofstream file(path_, std::ios::trunc);
  file << engine_exe << "\n";
  if (!file) throw Error(SystemErrorMessage("write \"" + path_ + "\"", errno));
}

ContainerRegistration::~ContainerRegistration() { unlink(path_.c_str()); }

namespace internal {

void RemoveRegisteredContainers(const std::string& scenario, DownReport* report) {
  const std::string dir = ScenarioDir(scenario);
  DIR* listing = opendir(dir.c_str());
  if (listing == nullptr) return;
  std::vector<std::string> files;
  while (const dirent* entry = readdir(listing)) {
    const std::string file = entry->d_name;
    if (file.rfind(kPrefix, 0) == 0) files.push_back(file);
  }
  closedir(listing);
  for (const std::string& file : files) {
    const std::string path = dir + "/" + file;
    const std::string name = file.substr(kPrefix.size());
    std::ifstream registration(path);
    std::string engine;
    std::getline(registration, engine);
    if (IsEngine(engine) && IsContainerName(name)) {
      // --time 0: SIGKILL at once, the scenario is going down. --ignore: a container that the
      // engine removed itself (`run --rm`) is no error.
      const int status =
          RunProgramQuietly({engine, "rm", "--force", "--ignore", "--time", "0", name});
      if (status != 0) {
        throw Error("down " + scenario + ": \"" + engine + " rm --force " + name +
                    "\" failed (status " + std::to_string(status) + "); the container is left");
      }
      ++report->containers_removed;
    }
    unlink(path.c_str());
  }
}

}  // namespace internal
}  // namespace sitlnet::nns

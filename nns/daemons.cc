// Root-namespace daemons of a scenario (`sitlnet medium`, `sitlnet physics`):
// pid files in the scenario's state directory, so that `down` stops them too,
// also after a crash of whatever started them.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <sstream>

#include "nns/nns_internal.h"
#include "nns/nns.h"

namespace sitlnet::nns {
namespace {

std::string PidFilePath(const std::string& scenario, const std::string& role) {
  return std::string(kStateDir) + "/" + scenario + "/" + role + ".pid";
}

// Field 22 of /proc/<pid>/stat: start time in clock ticks since boot. With the
// pid it names one process for good (a pid alone may be reused after a crash).
std::string StartTime(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const size_t paren = text.rfind(')');  // comm may contain spaces
  if (paren == std::string::npos) return "";
  std::istringstream fields(text.substr(paren + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
  }
  return field;
}

}  // namespace

namespace internal {

void WritePidFile(const std::string& scenario, const std::string& role) {
  const std::string path = PidFilePath(scenario, role);
  const pid_t pid = getpid();
  std::ofstream file(path, std::ios::trunc);
  file << pid << " " << StartTime(pid) << "\n";
  if (!file) throw Error(SystemErrorMessage("write \"" + path + "\"", errno));
}

}  // namespace internal

namespace internal {

void RequireScenarioUp(const std::string& scenario) {
  const std::string dir = std::string(kStateDir) + "/" + scenario;
  if (access(dir.c_str(), F_OK) != 0) {
    throw Error("scenario \"" + scenario + "\" is not up (no " + dir + "); run sitlnet up first");
  }
}

}  // namespace internal

DaemonRegistration::DaemonRegistration(const std::string& scenario, const std::string& role)
    : path_(PidFilePath(scenario, role)) {
  internal::RequireScenarioUp(scenario);
  internal::WritePidFile(scenario, role);
}

DaemonRegistration::~DaemonRegistration() { unlink(path_.c_str()); }

std::vector<ProcessInfo> RegisteredDaemons(const std::string& scenario) {
  std::vector<ProcessInfo> daemons;
  const std::string dir = std::string(kStateDir) + "/" + scenario;
  for (const char* role : {"medium", "physics", "run"}) {
    std::ifstream file(PidFilePath(scenario, role));
    pid_t pid = 0;
    std::string start_time;
    if (!(file >> pid >> start_time) || pid <= 1 || pid == getpid()) continue;
    if (StartTime(pid) != start_time) continue;  // exited; the pid may be someone else's now
    daemons.push_back(ProcessInfo{pid, role});
  }
  return daemons;
}

}  // namespace sitlnet::nns

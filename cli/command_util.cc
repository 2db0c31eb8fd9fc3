// Helpers shared by the command files.
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <optional>

#include "cli/commands.h"
#include "nns/nns.h"

namespace sitlnet::cli {

int ReportErrors(const char* command, int error_code, const std::function<int()>& body) {
  try {
    return body();
  } catch (const nns::PrivilegeError& e) {
    std::fprintf(stderr, "sitlnet %s: %s\n", command, e.what());
    return kExitPrivileges;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sitlnet %s: %s\n", command, e.what());
    return error_code;
  }
}

Scenario LoadByFileOrName(const std::string& what) {
  struct stat st {};
  if (stat(what.c_str(), &st) == 0) return LoadScenarioFile(what);
  const std::optional<nns::ScenarioState> state = nns::ReadScenarioState(what);
  if (!state) throw Error("no scenario file and no scenario up named \"" + what + "\"");
  return LoadScenarioFile(state->source_path);
}

}  // namespace sitlnet::cli

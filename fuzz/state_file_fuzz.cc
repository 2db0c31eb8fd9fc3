// The scenario state file's parser (nns::ParseState): /run/sitlnet/<scenario>/state is read, as
// root, by `down` (which kills processes in, and removes, what it names), `exec` and `status`.
// A text that parses names only the plan's own namespaces and veths (issue 17, finding 5: a
// newline in a field once added a robot line that sent `down` after docker0), and what
// FormatState writes of it reads back the same.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/common.h"
#include "nns/nns.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace nns = sitlnet::nns;
  const std::string text(reinterpret_cast<const char*>(data), size);
  nns::ScenarioState state;
  try {
    state = nns::ParseState(text, "fuzz");
  } catch (const sitlnet::Error&) {
    return 0;  // Refused in one line: what `down` does with a bad file.
  }
  for (const nns::OwnedRobot& robot : state.robots) {
    if (robot.netns != sitlnet::RobotNetnsName(state.name, robot.name)) __builtin_trap();
    if (robot.root_veth != sitlnet::RobotRootVethName(state.name, robot.index)) __builtin_trap();
  }
  const std::string written = nns::FormatState(state);
  if (nns::FormatState(nns::ParseState(written, "fuzz round trip")) != written) __builtin_trap();
  return 0;
}

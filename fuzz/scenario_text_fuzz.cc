// Scenario text (textproto + validation) from arbitrary bytes: every input either loads or
// throws sitlnet::Error; anything else (crash, other exception, sanitizer report) is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/common.h"
#include "scenario/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const sitlnet::Scenario scenario = sitlnet::LoadScenarioText(text, "fuzz.textproto");
    // A loaded scenario must have a consistent plan.
    if (scenario.robots.size() != static_cast<size_t>(scenario.spec.robot_size())) __builtin_trap();
  } catch (const sitlnet::Error&) {
  }
  return 0;
}

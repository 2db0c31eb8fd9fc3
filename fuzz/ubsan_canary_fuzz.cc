// A fuzz target with one deliberate bug: on the input "UB" it overflows a signed int. fuzz/run.sh
// runs it on that input and requires a failure, which proves that the fuzz build stops at a
// UBSan report instead of printing it and counting the input as clean (docs/security.md).
#include <cstddef>
#include <cstdint>
#include <limits>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  volatile int value = std::numeric_limits<int>::max();
  if (size == 2 && data[0] == 'U' && data[1] == 'B') value = value + 1;
  return value == 0 ? 1 : 0;
}

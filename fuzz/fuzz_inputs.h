// What several fuzz targets make from the fuzzer's bytes: numbers that include the values
// decoders get wrong (NaN, infinities, anything), the small lockstep scenario the network targets
// run on, and little-endian fields of the streams they check.
#ifndef SITLNET_FUZZ_FUZZ_INPUTS_H_
#define SITLNET_FUZZ_FUZZ_INPUTS_H_

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenario/scenario.h"

namespace sitlnet::fuzz {

// NaN, an infinity, a value in [low, high], or any double.
inline double OddOrInRange(FuzzedDataProvider& in, double low, double high) {
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
      return NAN;
    case 1:
      return in.ConsumeBool() ? INFINITY : -INFINITY;
    case 2:
      return in.ConsumeFloatingPointInRange<double>(low, high);
    default:
      return in.ConsumeFloatingPoint<double>();
  }
}

// Robots a, b, c (b 20 m from a, c 60 m from a), lockstep, δ_net 2 ms.
inline Scenario ThreeRobotScenario(const std::string& name) {
  return LoadScenarioText("name: \"" + name +
                              "\"\n"
                              "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                              "robot { name: \"b\" position_m { x: 20 y: 0 z: 1 } }\n"
                              "robot { name: \"c\" position_m { x: 0 y: 60 z: 1 } }\n"
                              "timing { iteration_us: 10000 physics_step_us: 1000 "
                              "network_step_us: 2000 pacing: PACING_LOCKSTEP seed: 1 }\n",
                          name + "_fuzz");
}

inline uint32_t Le32(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= uint32_t{static_cast<uint8_t>(bytes[at + i])} << (8 * i);
  return value;
}

}  // namespace sitlnet::fuzz

#endif  // SITLNET_FUZZ_FUZZ_INPUTS_H_

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

// Every channel effect on, with a radio that hears almost anything (path loss exponent 1,
// 30 dBm, sensitivity -200 dBm: a station 1e18 m away is still above it) and a wall: positions
// from a peer reach the propagation delay, fading, log-normal shadowing and obstacle code.
inline constexpr char kEveryEffectRadio[] =
    "radio { standard: STANDARD_80211G path_loss_exponent: 1 tx_power_dbm: 30 "
    "rx_sensitivity_dbm: -200 propagation_delay: true nakagami_fading: true "
    "lognormal_shadowing_sigma_db: 6 }\n"
    "obstacle { name: \"wall\" center_m { x: 10 y: 5 z: 1 } size_m { x: 1 y: 4 z: 4 } }\n";

// Robots a, b, c (b 20 m from a, c 60 m from a), lockstep, δ_net 2 ms; the default radio, or
// kEveryEffectRadio.
inline Scenario ThreeRobotScenario(const std::string& name, bool every_effect = false) {
  return LoadScenarioText("name: \"" + name +
                              "\"\n"
                              "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                              "robot { name: \"b\" position_m { x: 20 y: 0 z: 1 } }\n"
                              "robot { name: \"c\" position_m { x: 0 y: 60 z: 1 } }\n"
                              "timing { iteration_us: 10000 physics_step_us: 1000 "
                              "network_step_us: 2000 pacing: PACING_LOCKSTEP seed: 1 }\n" +
                              (every_effect ? kEveryEffectRadio : ""),
                          name + "_fuzz");
}

inline uint32_t Le32(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= uint32_t{static_cast<uint8_t>(bytes[at + i])} << (8 * i);
  return value;
}

}  // namespace sitlnet::fuzz

#endif  // SITLNET_FUZZ_FUZZ_INPUTS_H_

// What several fuzz targets make from the fuzzer's bytes: numbers that include the values
// decoders get wrong (NaN, infinities, anything), the small lockstep scenario the network targets
// run on, poses as a peer sends them, and little-endian fields of the streams they check.
#ifndef SITLNET_FUZZ_FUZZ_INPUTS_H_
#define SITLNET_FUZZ_FUZZ_INPUTS_H_

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenario/scenario.h"
#include "sitlnet/coordinator.pb.h"

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
// kEveryEffectRadio. `on_two_nodes`: a fleet (issue 35), a and c on node n0, b on n1.
inline Scenario ThreeRobotScenario(const std::string& name, bool every_effect = false,
                                   bool on_two_nodes = false) {
  const auto robot = [on_two_nodes](const char* robot, const char* node, const char* position) {
    return std::string("robot { name: \"") + robot + "\" " +
           (on_two_nodes ? std::string("node: \"") + node + "\" " : "") + "position_m { " +
           position + " } }\n";
  };
  return LoadScenarioText(
      "name: \"" + name + "\"\n" + robot("a", "n0", "x: 0 y: 0 z: 1") +
          robot("b", "n1", "x: 20 y: 0 z: 1") + robot("c", "n0", "x: 0 y: 60 z: 1") +
          (on_two_nodes ? "nodes { name: \"n0\" } nodes { name: \"n1\" }\n" : "") +
          "timing { iteration_us: 10000 physics_step_us: 1000 "
          "network_step_us: 2000 pacing: PACING_LOCKSTEP seed: 1 }\n" +
          (every_effect ? kEveryEffectRadio : ""),
      name + "_fuzz");
}

// The fleet of the node link fuzzers: ThreeRobotScenario on two nodes (n0: a, c; n1: b). Their
// rare cases take the largest value of a range: an input that ran out of bytes reads the
// smallest (FuzzedDataProvider), so short inputs stay on the common, cheap path.
inline const Scenario& ThreeRobotFleet() {
  static const Scenario scenario =
      ThreeRobotScenario("fzf", /*every_effect=*/false, /*on_two_nodes=*/true);
  return scenario;
}

// Poses of `robots` robots as a peer may send them: mostly with the counts of numbers a
// physics sends (velocities or none), sometimes any count; NaN, infinities and any double.
inline void FillPoses(FuzzedDataProvider& in, size_t robots, proto::coord::Poses* poses) {
  const bool any_count = in.ConsumeIntegralInRange(0, 3) == 3;
  const auto count = [&](size_t per_robot) {
    return any_count ? in.ConsumeIntegralInRange<size_t>(0, 4 * robots + 2) : per_robot * robots;
  };
  const size_t positions = count(3), orientations = count(4);
  const size_t velocities = in.ConsumeBool() ? count(3) : 0;
  for (size_t i = 0; i < positions; ++i) poses->add_position_m(OddOrInRange(in, -100, 100));
  for (size_t i = 0; i < orientations; ++i) poses->add_orientation_wxyz(OddOrInRange(in, -1, 1));
  for (size_t i = 0; i < velocities; ++i) poses->add_velocity_m_s(OddOrInRange(in, -20, 20));
}

inline uint32_t Le32(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= uint32_t{static_cast<uint8_t>(bytes[at + i])} << (8 * i);
  return value;
}

}  // namespace sitlnet::fuzz

#endif  // SITLNET_FUZZ_FUZZ_INPUTS_H_

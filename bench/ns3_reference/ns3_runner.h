// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Interface between the C++20 benchmark and its C++17 ns-3 half.
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_

#include <cstdint>

struct Ns3Outcome {
  double throughput_mbps = 0;
  double wall_s = 0;
};

// n saturated 802.11a stations in a ring (i -> i+1), 1500-byte packets, see
// ns3_side_by_side.cc for the setup. Returns payload throughput over the
// measured window and the wall time of Simulator::Run().
Ns3Outcome RunNs3Saturation(int n, double rate_mbps, double warmup_s, double measure_s,
                            uint32_t run);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_

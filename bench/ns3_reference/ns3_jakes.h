// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Samples of ns-3 3.37's Jakes fading, for ns3_jakes_side_by_side.cc (compiled apart: ns-3's
// headers are C++17 only).
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_JAKES_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_JAKES_H_

#include <complex>
#include <cstdint>
#include <vector>

// The complex gains of `processes` ns-3 JakesProcess objects (DopplerFrequencyHz, NumberOfOscillators
// as given), each attached to one JakesPropagationLossModel whose angles come from RNG run `run`,
// read at Simulator::Now() = 0, step_s, 2 step_s, ... (`steps` samples): [process][step].
std::vector<std::vector<std::complex<double>>> Ns3JakesGains(double doppler_hz, int oscillators,
                                                             int processes, double step_s,
                                                             int steps, uint32_t run);

// True if ns-3's JakesPropagationLossModel gives a -> b and b -> a the same power at the same
// instant over `pairs` pairs of mobility models (one process per unordered pair).
bool Ns3JakesIsSymmetric(int pairs, uint32_t run);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_JAKES_H_

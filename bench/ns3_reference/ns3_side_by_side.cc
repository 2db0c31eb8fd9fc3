// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
//
// Runs the same saturation scenarios in ns-3 3.37 (Debian's libns3-dev) and
// in mac_phy_sim, one after the other in one process, and prints throughput
// and wall time for both as a Markdown table (docs/validation.md).
//
// ns-3 setup (as its Bianchi validation): 802.11a ad hoc (non-QoS), constant
// rate, Yans channel with its defaults (log-distance, exponent 3, 46.6777 dB
// at 1 m; constant-speed propagation delay), NIST error model (the model
// mac_phy_sim implements), stations 1 mm apart, packet sockets offering
// 1500-byte packets faster than the medium can carry them, retry limits never
// reached. Ring: station i sends to i+1; measured over `measure` seconds
// after 1 s of warm-up.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "mac_phy_sim/test/saturation_harness.h"
#include "ns3_runner.h"

namespace {

struct Outcome {
  double throughput_mbps = 0;
  double wall_s = 0;
};

Outcome RunMacPhySim(int n, double rate_mbps, double warmup_s, double measure_s, uint64_t seed) {
  using namespace sitlnet::mac::testing;
  SaturationSetup setup;
  setup.stations = n;
  setup.rate_mbps = rate_mbps;
  setup.topology = Topology::kRing;
  setup.warmup_ns = static_cast<int64_t>(warmup_s * 1e9);
  setup.measure_ns = static_cast<int64_t>(measure_s * 1e9);
  setup.seed = seed;
  const auto start = std::chrono::steady_clock::now();
  const SaturationResult result = RunSaturation(setup);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {result.throughput_mbps, wall};
}

}  // namespace

int main(int argc, char** argv) {
  const double measure_s = argc > 1 ? std::atof(argv[1]) : 10;
  const double warmup_s = 1;
  struct Case {
    int n;
    double rate_mbps;
    double difs_table, eifs_table;  // docs/references.md#bianchi (0: not in the table)
  };
  const std::vector<Case> cases = {
      {5, 6, 4.7087, 4.6899},     {10, 6, 4.3453, 4.3197},    {5, 24, 16.2470, 16.0836},
      {10, 24, 15.1426, 14.9153}, {5, 54, 29.8324, 29.2861},  {10, 54, 28.1519, 27.3763},
      {20, 54, 26.2925, 25.3325}, {50, 54, 23.5618, 22.4162},
  };
  std::printf(
      "| rate Mb/s | n | Bianchi DIFS / EIFS table | ns-3 3.37 Mb/s | mac_phy_sim Mb/s |"
      " ns-3 simulated s per wall s | mac_phy_sim simulated s per wall s | speed-up |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Case& c : cases) {
    const Ns3Outcome ns3 = RunNs3Saturation(c.n, c.rate_mbps, warmup_s, measure_s, 1);
    const Outcome ours = RunMacPhySim(c.n, c.rate_mbps, warmup_s, measure_s, 1);
    const double total_s = warmup_s + measure_s;
    std::printf("| %g | %d | %.4f / %.4f | %.4f | %.4f | %.3f | %.1f | %.0fx |\n", c.rate_mbps, c.n,
                c.difs_table, c.eifs_table, ns3.throughput_mbps, ours.throughput_mbps,
                total_s / ns3.wall_s, total_s / ours.wall_s, ns3.wall_s / ours.wall_s);
    std::fflush(stdout);
  }
  return 0;
}

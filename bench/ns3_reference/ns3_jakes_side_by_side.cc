// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Jakes fading side by side: the statistics of ns-3 3.37's JakesProcess and of mac_phy_sim's
// (mac_phy_sim/jakes_process.h), measured by the same code (mac_phy_sim/test/fading_statistics),
// beside their closed forms; then saturated 802.11a links with Jakes fading in both simulators
// (ns3_runner's Yans channel with JakesPropagationLossModel after the log-distance model).
// Prints the Markdown tables of docs/validation.md's "Jakes fading".
// Usage: ns3_jakes_side_by_side [processes]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "mac_phy_sim/jakes_process.h"
#include "mac_phy_sim/test/fading_statistics.h"
#include "mac_phy_sim/test/saturation_harness.h"
#include "ns3_jakes.h"
#include "ns3_runner.h"

namespace {

using sitlnet::TimeNs;
using namespace sitlnet::mac;

double PercentApart(double sitlnet, double ns3) { return 100 * (sitlnet - ns3) / ns3; }

void Compare(const JakesParameters& parameters, int processes) {
  const TimeNs step_ns = 100 * sitlnet::kNsPerUs;
  const int steps = 10000;  // 1 s.
  FadingSamples ns3;
  ns3.step_s = step_ns / 1e9;
  ns3.gains = Ns3JakesGains(parameters.doppler_hz, parameters.oscillators, processes, ns3.step_s,
                            steps, 1);
  const FadingSamples ours = SampleJakesProcesses(parameters, processes, step_ns, steps, 1);
  std::printf("\n%g Hz, %d oscillators, %d processes each side, 1 s sampled every 0.1 ms:\n\n",
              parameters.doppler_hz, parameters.oscillators, processes);
  std::printf("| statistic | closed form | ns-3 3.37 | mac_phy_sim | apart | rule |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const int lag : {10, 20, 50, 100, 150, 200}) {
    const double x = 2 * std::numbers::pi * parameters.doppler_hz * lag * ours.step_s;
    const double a = Autocorrelation(ns3, lag).mean, b = Autocorrelation(ours, lag).mean;
    std::printf("| autocorrelation at %g ms | J0 = %.4f | %.4f | %.4f | %.4f | %s 0.01 |\n",
                lag * ours.step_s * 1e3, std::cyl_bessel_j(0.0, x), a, b, b - a,
                std::abs(b - a) <= 0.01 ? "within" : "**outside**");
  }
  const double pa = MeanPowerGain(ns3).mean, pb = MeanPowerGain(ours).mean;
  std::printf("| mean power gain | 1 | %.4f | %.4f | %.4f | %s 0.01 |\n", pa, pb, pb - pa,
              std::abs(pb - pa) <= 0.01 ? "within" : "**outside**");
  for (const double threshold_db : {0.0, -10.0, -20.0}) {
    const double rho = std::pow(10.0, threshold_db / 20);
    const FadeStatistics a = FadesBelow(ns3, rho * rho), b = FadesBelow(ours, rho * rho);
    const double crossings = PercentApart(b.crossings_per_s, a.crossings_per_s);
    const double fade = PercentApart(b.mean_fade_s, a.mean_fade_s);
    std::printf("| fades below %g dB per s | %.2f | %.2f | %.2f | %+.2f %% | %s 5 %% |\n",
                threshold_db, RayleighCrossingsPerS(parameters.doppler_hz, rho),
                a.crossings_per_s, b.crossings_per_s, crossings,
                std::abs(crossings) <= 5 ? "within" : "**outside**");
    std::printf("| average fade below %g dB, ms | %.3f | %.3f | %.3f | %+.2f %% | %s 5 %% |\n",
                threshold_db, RayleighMeanFadeS(parameters.doppler_hz, rho) * 1e3,
                a.mean_fade_s * 1e3, b.mean_fade_s * 1e3, fade,
                std::abs(fade) <= 5 ? "within" : "**outside**");
  }
}

double Mean(const std::vector<double>& x) {
  double sum = 0;
  for (double v : x) sum += v;
  return sum / x.size();
}

double StandardDeviation(const std::vector<double>& x) {
  const double mean = Mean(x);
  double sum = 0;
  for (double v : x) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / (x.size() - 1));
}

// One sender saturating a receiver `distance_m` away, 5 seeds each side (ns-3 RngRun 1-5,
// mac_phy_sim seeds 1-5), the windows of the matrix's Rayleigh cells. Rule: 5 % (ns-3's).
void CompareLinks() {
  std::printf("\nSaturated 802.11a links with Jakes fading (80 Hz, 20 oscillators), 1500 B, "
              "5 seeds each side:\n\n");
  std::printf("| link | ns-3 Mb/s (sd) | mac_phy_sim Mb/s (sd) | apart | rule |\n");
  std::printf("|---|---|---|---|---|\n");
  struct Link {
    double rate_mbps, distance_m, measure_s;
  };
  for (const Link& link : {Link{6, 40, 13.4}, Link{6, 70, 13.4}, Link{54, 15, 2.5}}) {
    sitlnet::side_by_side::Case c;
    c.standard = sitlnet::side_by_side::Standard::kA;
    c.rate_mbps = link.rate_mbps;
    c.topology = sitlnet::side_by_side::Topology::kLink;
    c.senders = 1;
    c.near_m = link.distance_m;
    c.unlimited_retries = false;
    c.warmup_s = 0.5;
    c.measure_s = link.measure_s;
    c.jakes = true;
    const sitlnet::mac::PhyInfo phy =
        sitlnet::mac::DerivePhyInfo(sitlnet::mac::testing::ConfigForCase(c, 1));
    const Ns3Radio radio{phy.reference_loss_db, phy.ack_rate_mbps, {}};
    std::vector<double> ns3, ours;
    for (int seed = 1; seed <= 5; ++seed) {
      ns3.push_back(RunNs3Case(c, radio, static_cast<uint32_t>(seed)).throughput_mbps);
      ours.push_back(
          sitlnet::mac::testing::RunCase(c, static_cast<uint64_t>(seed)).throughput_mbps);
    }
    const double apart = PercentApart(Mean(ours), Mean(ns3));
    std::printf("| %g Mb/s at %g m | %.4f (%.4f) | %.4f (%.4f) | %+.2f %% | %s 5 %% |\n",
                link.rate_mbps, link.distance_m, Mean(ns3), StandardDeviation(ns3), Mean(ours),
                StandardDeviation(ours), apart, std::abs(apart) <= 5 ? "within" : "**outside**");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int processes = argc > 1 ? std::atoi(argv[1]) : 400;
  std::printf("ns-3 JakesPropagationLossModel: a -> b and b -> a give the same power: %s\n",
              Ns3JakesIsSymmetric(20, 1) ? "yes" : "no");
  Compare(JakesParameters{80, 20}, processes);  // ns-3's defaults.
  Compare(JakesParameters{200, 8}, processes);
  CompareLinks();
  return 0;
}

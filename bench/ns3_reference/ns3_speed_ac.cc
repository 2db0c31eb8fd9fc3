// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
#include "ns3_speed_ac.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/mac_phy_sim/ac_saturation_cell.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"
#include "mac_phy_sim/test/side_by_side_case.h"
#include "ns3_runner.h"

namespace {

using sitlnet::side_by_side::Case;
using sitlnet::mac::bench::AcSaturationCell;
using sitlnet::mac::bench::kVhtMaxAmpduBytes;

double MeanOf(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double MedianOf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

std::string RangeOf(const std::vector<double>& values, const char* format) {
  char buf[64];
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  std::snprintf(buf, sizeof buf, (std::string(format) + "-" + format).c_str(), *lo, *hi);
  return buf;
}

// ns-3's radio for the cell: mac_phy_sim's 1 m loss, control rate and frequency, and the A-MPDU
// limit.
Ns3Radio RadioFor(const Case& c) {
  const sitlnet::mac::PhyInfo phy =
      sitlnet::mac::DerivePhyInfo(sitlnet::mac::testing::ConfigForCase(c, 1));
  Ns3Radio radio{phy.reference_loss_db, phy.ack_rate_mbps, {}};
  radio.path_loss_frequency_hz = phy.path_loss_frequency_hz;
  radio.be_max_ampdu_bytes = kVhtMaxAmpduBytes;
  return radio;
}

}  // namespace

// Speed at 802.11ac saturation with 64-MPDU A-MPDUs, ns-3 against mac_phy_sim in this process,
// `rounds` ABBA rounds per station count (round r: seed r on both sides; odd rounds ns-3 first,
// even rounds mac_phy_sim first); then mac_phy_sim's CPU per delivered MPDU with aggregation
// against aggregation off on the same cells, ABBA the same way. Medians over the rounds.
int PrintSpeedAc(int rounds, double measure_s) {
  std::printf(
      "802.11ac VHT MCS 9, 80 MHz, long GI, 1500 B, A-MPDU (BE_MaxAmpduSize %u), %d rounds ABBA, "
      "%.1f + %.1f s; medians (range)\n\n"
      "| senders | ns-3 simulated s per wall s | mac_phy_sim simulated s per wall s | speed-up, wall "
      "| ns-3 simulated s per CPU s | mac_phy_sim simulated s per CPU s | speed-up, CPU "
      "| ns-3 Mb/s | mac_phy_sim Mb/s | mac_phy_sim MPDUs per A-MPDU |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
      kVhtMaxAmpduBytes, rounds, 0.5, measure_s);
  const std::vector<int> sender_counts = {1, 5, 20};
  for (int n : sender_counts) {
    const Case c = AcSaturationCell(n, measure_s, true);
    const Ns3Radio radio = RadioFor(c);
    const double simulated_s = c.warmup_s + c.measure_s;
    std::vector<double> ns3_wall, ours_wall, wall_ratio, ns3_cpu, ours_cpu, cpu_ratio;
    std::vector<double> ns3_mbps, ours_mbps, per_ampdu;
    for (int r = 1; r <= rounds; ++r) {
      Ns3Outcome theirs;
      if (r % 2 == 1) theirs = RunNs3Case(c, radio, r);
      const sitlnet::mac::bench::TopUpOutcome ours = sitlnet::mac::bench::RunAcSaturationCell(c, r);
      if (r % 2 == 0) theirs = RunNs3Case(c, radio, r);
      ns3_wall.push_back(simulated_s / theirs.wall_s);
      ours_wall.push_back(simulated_s / ours.wall_s);
      wall_ratio.push_back(theirs.wall_s / ours.wall_s);
      ns3_cpu.push_back(simulated_s / theirs.cpu_s);
      ours_cpu.push_back(simulated_s / ours.cpu_s);
      cpu_ratio.push_back(theirs.cpu_s / ours.cpu_s);
      ns3_mbps.push_back(theirs.throughput_mbps);
      ours_mbps.push_back(ours.payload_mbps);
      per_ampdu.push_back(ours.mpdus_per_ampdu);
    }
    std::printf("| %d | %.3f (%s) | %.1f (%s) | %.0fx (%s) | %.3f (%s) | %.1f (%s) | %.0fx (%s) "
                "| %.2f | %.2f | %.1f |\n",
                n, MedianOf(ns3_wall), RangeOf(ns3_wall, "%.3f").c_str(), MedianOf(ours_wall),
                RangeOf(ours_wall, "%.1f").c_str(), MedianOf(wall_ratio),
                RangeOf(wall_ratio, "%.0f").c_str(), MedianOf(ns3_cpu),
                RangeOf(ns3_cpu, "%.3f").c_str(), MedianOf(ours_cpu),
                RangeOf(ours_cpu, "%.1f").c_str(), MedianOf(cpu_ratio),
                RangeOf(cpu_ratio, "%.0f").c_str(), MedianOf(ns3_mbps), MedianOf(ours_mbps),
                MedianOf(per_ampdu));
    std::fflush(stdout);
  }
  std::printf(
      "\nmac_phy_sim CPU per delivered MPDU, A-MPDU against aggregation off (same cells)\n\n"
      "| senders | A-MPDU: CPU us per MPDU | off: CPU us per frame | A-MPDU / off | A-MPDU Mb/s "
      "| off Mb/s |\n| --- | --- | --- | --- | --- | --- |\n");
  for (int n : sender_counts) {
    const Case on = AcSaturationCell(n, measure_s, true);
    const Case off = AcSaturationCell(n, measure_s, false);
    std::vector<double> on_us, off_us, on_mbps, off_mbps;
    for (int r = 1; r <= rounds; ++r) {
      auto run = [&](const Case& c, std::vector<double>* us, std::vector<double>* mbps) {
        const sitlnet::mac::bench::TopUpOutcome o =
            sitlnet::mac::bench::RunAcSaturationCell(c, r);
        const uint64_t mpdus = std::max<uint64_t>(1, o.mpdus_delivered_all);
        us->push_back(o.cpu_s * 1e6 / static_cast<double>(mpdus));
        mbps->push_back(o.payload_mbps);
      };
      if (r % 2 == 1) run(on, &on_us, &on_mbps);
      run(off, &off_us, &off_mbps);
      if (r % 2 == 0) run(on, &on_us, &on_mbps);
    }
    std::printf("| %d | %.3f (%s) | %.3f (%s) | %.2f | %.2f | %.2f |\n", n, MedianOf(on_us),
                RangeOf(on_us, "%.3f").c_str(), MedianOf(off_us), RangeOf(off_us, "%.3f").c_str(),
                MedianOf(on_us) / MedianOf(off_us), MedianOf(on_mbps), MedianOf(off_mbps));
    std::fflush(stdout);
  }
  return 0;
}

// One sender's saturation throughput in the speed comparison's 802.11ac cell (AcSaturationCell),
// both sides, `seeds` seeds each: the figure a real iperf3 flow over the same radio is held to
// (bench/ns3_reference/ac_iperf3_dilated.sh). Payload throughput of 1500-byte packets (IPv4
// packets of 1500 B: iperf3 -u -l 1472).
int PrintSaturationAc(int seeds, double measure_s) {
  const Case c = AcSaturationCell(1, measure_s, true);
  const Ns3Radio radio = RadioFor(c);
  std::vector<double> ns3, ours;
  for (int seed = 1; seed <= seeds; ++seed) {
    ns3.push_back(RunNs3Case(c, radio, static_cast<uint32_t>(seed)).throughput_mbps);
    ours.push_back(
        sitlnet::mac::bench::RunAcSaturationCell(c, static_cast<uint64_t>(seed)).payload_mbps);
  }
  std::printf("ns-3 %.3f Mb/s (seeds %s, %.1f s each)\n", MeanOf(ns3),
              RangeOf(ns3, "%.3f").c_str(), measure_s);
  std::printf("mac_phy_sim %.3f Mb/s (seeds %s; light driver)\n", MeanOf(ours),
              RangeOf(ours, "%.3f").c_str());
  return 0;
}

// mac_phy_sim benchmark: simulated seconds per wall second.
//   saturation, n = 1, 5, 10, 20, 50: 802.11a 54 Mb/s, 1500-byte payloads, ring;
//   broadcast64: 64 moving stations, each broadcasting 200 B at 10 Hz, among
//   100 or 1000 obstacles (positions updated every 10 ms, as the coordinator does);
//   hidden: the hidden pair A -> B <- C, 40 m apart, 11a 6 Mb/s, 1500 B,
//   saturated: half the frames overlap, so the error model runs on every chunk.
// Medians of --runs runs (different seeds). Prints a Markdown table and, with
// --csv FILE, "scenario,n,sim_s_per_wall_s,sim_s_per_cpu_s,us_per_tx,us_per_tx_per_station,
// transmissions" (the last: the median run's count, for instruction counts per transmission).
// --validation prints the whole ns-3 Bianchi table instead (docs/validation.md).
// --rows LIST runs only the rows named in the comma-separated LIST: sat1, sat5,
// sat10, sat20, sat50, bcast, bcast-fading, bcast-jakes, bcast-jakes-speed, bcast-delay,
// bcast1000, hidden, ac1, ac5, ac20, ac1-off, ac5-off, ac20-off (e.g.
// --rows bcast,bcast-fading for the fading cost alone). The ac rows are the 802.11ac cell of
// bench/ns3_reference/ac_speed.sh (ac_saturation_cell.h: VHT MCS 9, 80 MHz, 64-MPDU A-MPDUs, or
// "-off" without aggregation), n senders, so they can be profiled without ns-3; their "CPU us per
// transmission" column counts delivered MPDUs instead of transmissions.
// --error-model nist|table: the error model of the broadcast and hidden rows (default
// nist); bench/mac_phy_sim/error_model_ab.sh alternates the two (ABBA).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench/mac_phy_sim/ac_saturation_cell.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

// Wall time is what the issue asks for; CPU time of this process is also
// reported because the 2-core host is shared and wall time includes the time
// other processes held the cores.
struct Sample {
  double sim_per_wall = 0;  // Simulated seconds per wall second.
  double sim_per_cpu = 0;   // Simulated seconds per CPU second of this process.
  double us_per_tx = 0;     // CPU microseconds per transmission (DATA + ACK + RTS + CTS).
  uint64_t transmissions = 0;
};

// The error model of the broadcast rows (--error-model).
MediumConfig::ErrorModel g_error_model = MediumConfig::ErrorModel::kNist;

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

double WallSeconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

uint64_t Transmissions(const Medium& medium) {
  uint64_t total = 0;
  for (int i = 0; i < medium.station_count(); ++i) {
    const StationCounters& c = medium.counters(i);
    total += c.data_tx + c.ack_tx + c.rts_tx + c.cts_tx;
  }
  return total;
}

// The sample of a run of `seconds` of virtual time that started at `start`
// (wall) and `cpu_start` (CPU) and made `transmissions`.
Sample Measured(double seconds, std::chrono::steady_clock::time_point start, double cpu_start,
                uint64_t transmissions) {
  const double wall = WallSeconds(start);
  const double cpu = CpuSeconds() - cpu_start;
  return {seconds / wall, seconds / cpu, cpu * 1e6 / std::max<uint64_t>(1, transmissions),
          transmissions};
}

Sample Saturation(int n, double seconds, uint64_t seed) {
  // The medium's own cost, with the light driver (testing::RunTopUpSaturation).
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  return Measured(seconds, start, cpu_start, testing::RunTopUpSaturation(n, seconds, seed));
}

// The 802.11ac cell (ac_saturation_cell.h), 0.5 s of warm-up and `seconds`; per delivered MPDU.
Sample AcSaturation(int n, bool ampdu, double seconds, uint64_t seed) {
  const bench::TopUpOutcome o =
      bench::RunAcSaturationCell(bench::AcSaturationCell(n, seconds, ampdu), seed);
  const double simulated_s = 0.5 + seconds;
  return {simulated_s / o.wall_s, simulated_s / o.cpu_s,
          o.cpu_s * 1e6 / static_cast<double>(std::max<uint64_t>(1, o.mpdus_delivered_all)),
          o.mpdus_delivered_all};
}

// The channel effect a broadcast row adds (docs/mac_phy_sim.md), with ns-3's defaults:
// Nakagami fading per frame and receiver, Jakes fading per pair (its Doppler fixed or from
// the speeds), propagation delay.
enum class Effect { kNone, kNakagami, kJakes, kJakesFromSpeed, kDelay };

Sample Broadcast64(double seconds, uint64_t seed, int obstacles, double area_m, double max_box_m,
                   Effect effect = Effect::kNone,
                   MediumConfig::PathLoss path_loss = MediumConfig::PathLoss::kLogDistance) {
  MediumConfig config;
  config.seed = seed;
  config.path_loss_model = path_loss;
  config.nakagami_fading = effect == Effect::kNakagami;
  config.jakes_fading = effect == Effect::kJakes || effect == Effect::kJakesFromSpeed;
  config.jakes_doppler_from_speed = effect == Effect::kJakesFromSpeed;
  config.propagation_delay = effect == Effect::kDelay;
  config.error_model = g_error_model;
  Medium medium(config);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, area_m), size(max_box_m / 6, max_box_m), yaw(0, 90),
      step(-0.1, 0.1);
  for (int k = 0; k < obstacles; ++k) {
    medium.AddObstacle(Box{{pos(rng), pos(rng), 10}, {size(rng), size(rng), 20}, yaw(rng)});
  }
  const int n = 64;
  std::vector<Vec3d> where(n);
  std::vector<std::vector<uint8_t>> frames;
  std::vector<TimeNs> phase(n);
  const MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  for (int i = 0; i < n; ++i) {
    where[i] = Vec3d{pos(rng), pos(rng), 5};
    medium.AddStation(RobotMac(i), where[i]);
    frames.push_back(testing::MakeEthernetFrame(broadcast, RobotMac(i), 200 - 14));
    phase[i] = static_cast<TimeNs>(rng() % (100 * kNsPerMs));
  }
  const TimeNs step_ns = 10 * kNsPerMs;  // Network step of the default scenario.
  const TimeNs end_ns = static_cast<TimeNs>(seconds * 1e9);
  std::vector<Delivery> deliveries;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  for (TimeNs t = 0; t < end_ns; t += step_ns) {
    for (int i = 0; i < n; ++i) {
      // 10 m/s random walk: every position changes every step.
      where[i].x += 100 * step(rng) * step_ns / 1e9 * 10;
      where[i].y += 100 * step(rng) * step_ns / 1e9 * 10;
      medium.SetStationPosition(i, where[i], t);
      // 10 Hz: one frame per 100 ms at the station's phase.
      const TimeNs next =
          t + ((phase[i] - t) % (100 * kNsPerMs) + 100 * kNsPerMs) % (100 * kNsPerMs);
      if (next < t + step_ns) medium.SubmitFrame(i, frames[i], next);
    }
    deliveries.clear();
    medium.AdvanceTo(t + step_ns, &deliveries);
  }
  return Measured(seconds, start, cpu_start, Transmissions(medium));
}

// The hidden pair of docs/validation.md with a light driver: A (0 m) and C
// (80 m) send 1500-byte frames to B (40 m) at 6 Mb/s, queues topped up to 16
// frames every 2 ms; the standard's retry limits.
Sample HiddenPair(double seconds, uint64_t seed) {
  MediumConfig config;
  config.seed = seed;
  config.rate_mbps = 6;
  config.error_model = g_error_model;
  Medium medium(config);
  for (int i = 0; i < 3; ++i) medium.AddStation(RobotMac(i), Vec3d{40.0 * i, 0, 0});
  const int senders[] = {0, 2};
  std::vector<std::vector<uint8_t>> frames;
  for (int i : senders)
    frames.push_back(testing::MakeEthernetFrame(RobotMac(1), RobotMac(i), 1500));
  const TimeNs step_ns = 2 * kNsPerMs;
  const TimeNs end_ns = static_cast<TimeNs>(seconds * 1e9);
  std::vector<Delivery> deliveries;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  for (TimeNs t = 0; t < end_ns; t += step_ns) {
    for (int k = 0; k < 2; ++k) {
      while (medium.queued_frames(senders[k]) < 16) {
        medium.SubmitFrame(senders[k], frames[k], t);
        medium.AdvanceTo(t, nullptr);  // Enqueue now so queued_frames() sees it.
      }
    }
    deliveries.clear();
    medium.AdvanceTo(t + step_ns, &deliveries);
  }
  return Measured(seconds, start, cpu_start, Transmissions(medium));
}

// The full ns-3 Bianchi table (docs/references.md#bianchi), both topologies, ~25,000 frames
// per point as in the tests: measured throughput, error vs each table, and
// ns-3's pass rule.
void PrintValidation() {
  struct Row {
    double rate;
    double difs[6], eifs[6];
  };
  const int ns[6] = {5, 10, 15, 20, 30, 50};
  const Row rows[] = {
      {6,
       {4.7087, 4.3453, 4.1397, 3.9899, 3.7824, 3.5071},
       {4.6899, 4.3197, 4.1107, 3.9589, 3.7490, 3.4711}},
      {24,
       {16.2470, 15.1426, 14.4904, 14.0072, 13.3288, 12.4144},
       {16.0836, 14.9153, 14.2327, 13.7300, 13.0281, 12.0889}},
      {54,
       {29.8324, 28.1519, 27.0948, 26.2925, 25.1434, 23.5618},
       {29.2861, 27.3763, 26.2078, 25.3325, 24.0944, 22.4162}},
  };
  std::printf(
      "| rate Mb/s | n | topology | measured Mb/s | vs DIFS table | vs EIFS table | "
      "collision p | pass (<= 1.5 %%) |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Row& row : rows) {
    for (int k = 0; k < 6; ++k) {
      for (const auto topology : {testing::Topology::kRing, testing::Topology::kSink}) {
        testing::SaturationSetup setup;
        setup.stations = ns[k];
        setup.rate_mbps = row.rate;
        setup.topology = topology;
        setup.measure_ns = static_cast<TimeNs>(25000 * 12000.0 / (row.eifs[k] * 1e6) * 1e9);
        const testing::SaturationResult r = testing::RunSaturation(setup);
        const double e_difs = 100 * (r.throughput_mbps / row.difs[k] - 1);
        const double e_eifs = 100 * (r.throughput_mbps / row.eifs[k] - 1);
        const bool pass = std::min(std::fabs(e_difs), std::fabs(e_eifs)) <= 1.5;
        std::printf("| %g | %d | %s | %.4f | %+.2f %% | %+.2f %% | %.4f | %s |\n", row.rate, ns[k],
                    topology == testing::Topology::kRing ? "ring" : "sink", r.throughput_mbps,
                    e_difs, e_eifs, r.collision_probability, pass ? "yes" : "no");
        std::fflush(stdout);
      }
    }
  }
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace
}  // namespace sitlnet::mac

int main(int argc, char** argv) {
  using namespace sitlnet::mac;
  int runs = 5;
  double seconds = 10;
  const char* csv_path = nullptr;
  std::string rows;  // Empty: every row.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--runs" && has_value) {
      runs = std::atoi(argv[++i]);
    } else if (arg == "--seconds" && has_value) {
      seconds = std::atof(argv[++i]);
    } else if (arg == "--csv" && has_value) {
      csv_path = argv[++i];
    } else if (arg == "--rows" && has_value) {
      rows = std::string(",") + argv[++i] + ",";
    } else if (arg == "--error-model" && has_value &&
               (std::strcmp(argv[i + 1], "nist") == 0 || std::strcmp(argv[i + 1], "table") == 0)) {
      g_error_model = std::strcmp(argv[++i], "table") == 0 ? MediumConfig::ErrorModel::kTableBased
                                                           : MediumConfig::ErrorModel::kNist;
    } else if (arg == "--validation") {
      PrintValidation();
      return 0;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--runs N] [--seconds S] [--csv FILE] [--rows LIST]"
                   " [--error-model nist|table] | --validation\n",
                   argv[0]);
      return 2;
    }
  }
  auto wanted = [&](const std::string& key) {
    return rows.empty() || rows.find("," + key + ",") != std::string::npos;
  };
  FILE* csv = csv_path ? std::fopen(csv_path, "w") : nullptr;
  std::printf(
      "| scenario | n | simulated s per wall s | simulated s per CPU s | CPU us per transmission |"
      " CPU us per transmission per station |\n| --- | --- | --- | --- | --- | --- |\n");
  auto report = [&](const char* name, int n, const std::vector<Sample>& samples) {
    std::vector<double> wall_rate, cpu_rate, cost, transmissions;
    for (const Sample& s : samples) {
      wall_rate.push_back(s.sim_per_wall);
      cpu_rate.push_back(s.sim_per_cpu);
      cost.push_back(s.us_per_tx);
      transmissions.push_back(static_cast<double>(s.transmissions));
    }
    const double w = Median(wall_rate), r = Median(cpu_rate), c = Median(cost);
    std::printf("| %s | %d | %.1f | %.1f | %.3f | %.4f |\n", name, n, w, r, c, c / n);
    if (csv) {
      std::fprintf(csv, "%s,%d,%.3f,%.3f,%.4f,%.5f,%.0f\n", name, n, w, r, c, c / n,
                   Median(transmissions));
    }
    std::fflush(stdout);
  };
  for (int n : {1, 5, 10, 20, 50}) {
    if (!wanted("sat" + std::to_string(n))) continue;
    std::vector<Sample> samples;
    for (int k = 0; k < runs; ++k) samples.push_back(Saturation(n, seconds, 1 + k));
    report("saturation 11a 54 Mb/s 1500 B", n, samples);
  }
  for (int n : {1, 5, 20}) {
    for (bool ampdu : {true, false}) {
      if (!wanted("ac" + std::to_string(n) + (ampdu ? "" : "-off"))) continue;
      std::vector<Sample> ac;
      for (int k = 0; k < runs; ++k) ac.push_back(AcSaturation(n, ampdu, seconds, 1 + k));
      report(ampdu ? "saturation 11ac MCS 9 80 MHz 1500 B, 64-MPDU A-MPDUs (per MPDU)"
                   : "saturation 11ac MCS 9 80 MHz 1500 B, no aggregation (per MPDU)",
             n, ac);
    }
  }
  std::vector<Sample> samples;
  if (wanted("bcast")) {
    for (int k = 0; k < runs; ++k) samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30));
    report("broadcast 200 B @ 10 Hz, 100 obstacles (300 m square), all moving", 64, samples);
  }
  if (wanted("bcast-fading")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30, Effect::kNakagami));
    }
    report("the same with Nakagami fading (ns-3 defaults)", 64, samples);
  }
  if (wanted("bcast-jakes")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30, Effect::kJakes));
    }
    report("the same with Jakes fading (ns-3 defaults)", 64, samples);
  }
  if (wanted("bcast-jakes-speed")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30, Effect::kJakesFromSpeed));
    }
    report("the same with Jakes fading, Doppler from speed", 64, samples);
  }
  if (wanted("bcast-delay")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30, Effect::kDelay));
    }
    report("the same with propagation delay", 64, samples);
  }
  if (wanted("bcast-3gpp")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 100, 300, 30, Effect::kNone,
                                    MediumConfig::PathLoss::kThreeGppV2vUrban));
    }
    report("the same with 3GPP V2V urban path loss", 64, samples);
  }
  if (wanted("bcast1000")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) {
      samples.push_back(Broadcast64(6 * seconds, 1 + k, 1000, 500, 10));
    }
    report("broadcast 200 B @ 10 Hz, 1000 obstacles (500 m square), all moving", 64, samples);
  }
  if (wanted("hidden")) {
    samples.clear();
    for (int k = 0; k < runs; ++k) samples.push_back(HiddenPair(6 * seconds, 1 + k));
    report("hidden pair 40 m, 11a 6 Mb/s, 1500 B, saturated", 3, samples);
  }
  if (csv) std::fclose(csv);
  return 0;
}

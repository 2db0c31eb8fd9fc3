// Minstrel rate control for 802.11a/b/g, as ns-3 3.37's MinstrelWifiManager
// (src/wifi/model/rate-control/minstrel-wifi-manager.cc, itself after Linux's
// rc80211_minstrel.c): per destination, success counts per rate folded every
// update interval into an EWMA success probability (scaled to 18000), a
// throughput per rate from it and the rate's perfect TX time, a random sample
// table for look-around frames, and a multi-rate retry chain. Rates are
// indices into the sender's supported-mode list (ns-3's GetSupported order).
// Pure algorithm: no medium state; time comes in as now_ns.
#ifndef SITLNET_MAC_PHY_SIM_MINSTREL_H_
#define SITLNET_MAC_PHY_SIM_MINSTREL_H_

#include <cstdint>
#include <random>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// Uniform integer in [0, max_inclusive] (ns-3's UniformRandomVariable::GetInteger(0, max)).
int UniformInclusive(std::mt19937_64& rng, int max_inclusive);

// ns-3's InitSampleTable, which MinstrelWifiManager and MinstrelHtWifiManager write alike: each
// of `table`'s columns ([row][column], rows x columns, all 0) becomes a random permutation of
// 0 .. rows - 1. ns-3 marks free cells by 0, which is also row 0's value, so later values may
// land on 0's cell; the one cell left over holds 0 either way. Kept as ns-3 draws it.
void FillSampleTable(std::mt19937_64& rng, std::vector<std::vector<int>>& table);

// What the algorithm knows of the sender's PHY.
struct MinstrelPhy {
  // Per supported mode: the PPDU duration of a config.packet_bytes PSDU (long preamble).
  std::vector<TimeNs> perfect_tx_ns;
  TimeNs sifs_ns = 0, slot_ns = 0;
  // ns-3's WifiPhy::GetAckTxTime: 44 us (11a), 304 us (11b and 11g, which configures 11b first).
  TimeNs ack_tx_ns = 0;
};

// ns-3's RateInfo: one rate's statistics for one destination.
struct MinstrelRateStats {
  TimeNs perfect_tx_ns = 0;
  uint32_t retry_count = 1, adjusted_retry_count = 1;
  uint32_t attempts = 0, successes = 0;  // Since the last statistics update.
  uint32_t probability = 0;              // Of the last interval, scaled to 18000.
  uint32_t ewma_probability = 0;         // Scaled to 18000.
  uint32_t throughput = 0;               // ewma_probability x frames per second.
  uint32_t previous_attempts = 0, previous_successes = 0;
  uint64_t success_history = 0, attempt_history = 0;
  uint8_t samples_skipped = 0;
  int sample_limit = 0;  // -1: no limit; 0: never sampled.
};

// ns-3's MinstrelWifiRemoteStation: the state kept per destination.
struct MinstrelRemote {
  TimeNs next_stats_update_ns = 0;
  int column = 0, index = 0;
  int max_tp_rate = 0, max_tp_rate2 = 0, max_prob_rate = 0;
  int total_packets = 0, sample_packets = 0, samples_deferred = 0;
  bool is_sampling = false, sample_deferred = false;
  int sample_rate = 0;
  uint32_t short_retry = 0, long_retry = 0, retry = 0;
  int tx_rate = 0;  // The rate of the next attempt.
  std::vector<MinstrelRateStats> rates;
  std::vector<std::vector<int>> sample_table;  // [rate][column].
};

class Minstrel {
 public:
  // `rng` draws the sample tables (one stream per sender, as ns-3 has one per manager).
  Minstrel(MinstrelPhy phy, const MediumConfig::Minstrel& config, uint64_t seed);

  // ns-3's DoCreateStation + CheckInit: a destination first seen at `now_ns`.
  MinstrelRemote NewRemote(TimeNs now_ns);

  // Events of ns-3's WifiRemoteStationManager, named as there.
  static void ReportRtsFailed(MinstrelRemote& r) { ++r.short_retry; }
  static void ReportFinalRtsFailed(MinstrelRemote& r) { UpdateRetry(r); }
  void ReportDataFailed(MinstrelRemote& r) const { UpdateRate(r); }
  void ReportDataOk(MinstrelRemote& r, TimeNs now_ns) const;
  void ReportFinalDataFailed(MinstrelRemote& r, TimeNs now_ns) const;
  // False once the frame used up the retry chain (ns-3's DoNeedRetransmission).
  static bool NeedRetransmission(const MinstrelRemote& r) { return r.long_retry < CountRetries(r); }
  // ns-3's MinstrelWifiManager keeps the base class's DoReportAmpduTxStatus, which ignores it.
  static void ReportAmpduTxStatus(MinstrelRemote& /*r*/, int /*mpdus_ok*/, int /*mpdus_failed*/,
                                  TimeNs /*now_ns*/) {}

  // Exposed for tests: ns-3's UpdateStats (no-op before next_stats_update_ns), the retry chain
  // length, and the expected time of a frame sent with `long_retries` retries.
  void UpdateStats(MinstrelRemote& r, TimeNs now_ns) const;
  static uint32_t CountRetries(const MinstrelRemote& r);
  TimeNs UnicastTimeNs(TimeNs data_ns, uint32_t long_retries) const;
  int rate_count() const { return static_cast<int>(phy_.perfect_tx_ns.size()); }

 private:
  void UpdateRate(MinstrelRemote& r) const;
  int FindRate(MinstrelRemote& r) const;
  int NextSample(MinstrelRemote& r) const;
  static void UpdatePacketCounters(MinstrelRemote& r);
  static void UpdateRetry(MinstrelRemote& r);
  void InitSampleTable(MinstrelRemote& r);

  MinstrelPhy phy_;
  MediumConfig::Minstrel config_;
  std::mt19937_64 rng_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MINSTREL_H_

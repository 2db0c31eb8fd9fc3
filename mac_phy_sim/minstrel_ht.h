// Minstrel-HT rate control for 802.11n/ac, as ns-3 3.37's MinstrelHtWifiManager
// (src/wifi/model/rate-control/minstrel-ht-wifi-manager.cc, after Linux's
// rc80211_minstrel_ht.c). Rates come in groups of one (spatial streams, guard
// interval, channel width) each, with ns-3's group ids and its global rate
// index group x rates_per_group + rate. Per destination: success counts per
// rate folded every update interval into an EWMA success probability (0-100),
// a throughput from it and the rate's first-MPDU time, the two best-throughput
// rates and a best-probability rate over all groups, a sample table walked
// group by group, and a retry chain. A-MPDU outcomes count per MPDU.
// Pure algorithm: no medium state; time comes in as now_ns.
#ifndef SITLNET_MAC_PHY_SIM_MINSTREL_HT_H_
#define SITLNET_MAC_PHY_SIM_MINSTREL_HT_H_

#include <cstdint>
#include <random>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// ns-3's McsGroup as the sender and its destination both support it (sitlnet's stations all
// have the same radio, as an ad hoc ns-3 station assumes of its peers).
struct MinstrelHtGroup {
  bool supported = false;
  int streams = 1;
  // By rate id (rates_per_group entries; empty for an unsupported group): whether the MCS
  // exists in this group, and ns-3's CalculateMpduTxDuration of packet_bytes as the first and
  // as a middle MPDU of an A-MPDU.
  std::vector<bool> rate_supported;
  std::vector<TimeNs> first_mpdu_ns, middle_mpdu_ns;
};

// What the algorithm knows of the sender's PHY.
struct MinstrelHtPhy {
  // ns-3's m_numRates: 8 on an HT PHY, 10 on a VHT one.
  int rates_per_group = 8;
  // ns-3's m_minstrelGroups in its group-id order: 16 HT groups (GetHtGroupId), then on a VHT
  // PHY 64 VHT groups (GetVhtGroupId).
  std::vector<MinstrelHtGroup> groups;
  TimeNs slot_ns = 0, sifs_ns = 0;
  TimeNs block_ack_tx_ns = 0;  // ns-3's WifiPhy::GetBlockAckTxTime: 68 us for n/ac.
};

// ns-3's group ids: HT 4 x 2 x (width index) + 4 x (GI index) + streams - 1, width index 0 for
// 20 MHz and 1 for 40, GI index 1 for 400 ns; VHT 16 + 8 x 2 x (width index) + 8 x (GI index)
// + streams - 1, width index 0-3 for 20-160 MHz.
int MinstrelHtGroupId(int streams, bool short_guard_interval, int channel_width_mhz);
int MinstrelVhtGroupId(int streams, bool short_guard_interval, int channel_width_mhz);
inline constexpr int kMinstrelHtGroups = 16;   // MAX_HT_SUPPORTED_STREAMS x MAX_HT_STREAM_GROUPS
inline constexpr int kMinstrelVhtGroups = 64;  // MAX_VHT_SUPPORTED_STREAMS x MAX_VHT_STREAM_GROUPS

// ns-3's MinstrelHtRateInfo: one rate's statistics for one destination.
struct MinstrelHtRateStats {
  bool supported = false;
  TimeNs perfect_tx_ns = 0;   // The first-MPDU time.
  uint32_t retry_count = 0;   // Attempts at this rate in the retry chain.
  bool retry_updated = false;  // retry_count computed since the last statistics update.
  uint32_t attempts = 0, successes = 0;  // Since the last statistics update (MPDUs).
  double probability = 0;       // Of the last interval with attempts, 0-100 (whole numbers).
  double ewma_probability = 0;  // 0-100.
  double throughput = 0;        // Frames per second: min(ewma, 90) / perfect time; 0 below 10.
  uint32_t previous_attempts = 0, previous_successes = 0;
  uint32_t samples_skipped = 0;  // Updates without attempts.
  uint64_t success_history = 0, attempt_history = 0;
};

// ns-3's MinstrelHtWifiRemoteStation: the state kept per destination. Rates by global index.
struct MinstrelHtRemote {
  struct GroupCursor {
    int column = 0, index = 0;  // This group's place in the sample table.
  };
  TimeNs next_stats_update_ns = 0;
  int max_tp_rate = 0, max_tp_rate2 = 0, max_prob_rate = 0;
  int tx_rate = 0;  // The rate of the next attempt.
  int sample_rate = 0, sample_group = 0;
  bool is_sampling = false;
  // MPDUs; unsigned, as ns-3's, so that the reset at ~0 is defined.
  uint32_t total_packets = 0, sample_packets = 0;
  uint32_t sample_wait = 0, sample_tries = 4, sample_count = 16, samples_slow = 0;
  uint32_t avg_ampdu_len = 1, ampdu_len = 0, ampdu_packet_count = 0;
  uint32_t short_retry = 0, long_retry = 0;
  std::vector<MinstrelHtRateStats> rates;  // [group x rates_per_group + rate].
  std::vector<GroupCursor> groups;
  std::vector<std::vector<int>> sample_table;  // [rate id][column], shared by the groups.
};

class MinstrelHt {
 public:
  // `seed` starts the stream the sample tables are drawn from (one per sender, as ns-3 has one
  // per manager). update_stats_ns is config.ht_update_stats_ns (ns-3's UpdateStatistics).
  MinstrelHt(MinstrelHtPhy phy, const MediumConfig::Minstrel& config, uint64_t seed);

  // ns-3's DoCreateStation + CheckInit (InitSampleTable, RateInit): a destination first seen at
  // `now_ns`.
  MinstrelHtRemote NewRemote(TimeNs now_ns);

  // Events of ns-3's WifiRemoteStationManager, named as there.
  static void ReportRtsFailed(MinstrelHtRemote& r) { ++r.short_retry; }
  static void ReportFinalRtsFailed(MinstrelHtRemote& r) { UpdateRetry(r); }
  void ReportDataFailed(MinstrelHtRemote& r) const;
  void ReportDataOk(MinstrelHtRemote& r, TimeNs now_ns) const;
  void ReportFinalDataFailed(MinstrelHtRemote& r, TimeNs now_ns) const;
  void ReportAmpduTxStatus(MinstrelHtRemote& r, int mpdus_ok, int mpdus_failed,
                           TimeNs now_ns) const;
  // False once the frame used up the retry chain (ns-3's DoNeedRetransmission).
  bool NeedRetransmission(const MinstrelHtRemote& r) const {
    return r.long_retry < CountRetries(r);
  }

  // Exposed for tests: ns-3's UpdateStats (unconditional: callers check the time), the retry
  // chain's length, a rate's retry count, FindRate, and the index arithmetic.
  void UpdateStats(MinstrelHtRemote& r, TimeNs now_ns) const;
  uint32_t CountRetries(const MinstrelHtRemote& r) const;
  void CalculateRetransmits(MinstrelHtRemote& r, int index) const;
  int FindRate(MinstrelHtRemote& r) const;
  int Index(int group, int rate) const { return group * phy_.rates_per_group + rate; }
  int GroupOf(int index) const { return index / phy_.rates_per_group; }
  int RateOf(int index) const { return index % phy_.rates_per_group; }
  const MinstrelHtPhy& phy() const { return phy_; }

 private:
  void UpdateRate(MinstrelHtRemote& r) const;
  static void UpdateRetry(MinstrelHtRemote& r) { r.short_retry = r.long_retry = 0; }
  static void UpdatePacketCounters(MinstrelHtRemote& r, int mpdus_ok, int mpdus_failed);
  void AfterFrame(MinstrelHtRemote& r, TimeNs now_ns) const;
  int NextSample(MinstrelHtRemote& r) const;
  void SetNextSample(MinstrelHtRemote& r) const;
  void SetBestStationThRates(MinstrelHtRemote& r, int index) const;
  void SetBestProbabilityRate(MinstrelHtRemote& r, int index) const;
  int LowestIndex(const MinstrelHtRemote& r) const;

  MinstrelHtPhy phy_;
  MediumConfig::Minstrel config_;
  std::mt19937_64 rng_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MINSTREL_HT_H_

// ns-3 3.37's MinstrelHtWifiManager, function by function (names as there), with
// its arithmetic and its quirks kept, so both pick the same rates. Left out: the
// per-group best rates (ns-3 keeps them but decides nothing by them), the EWMSD
// (statistics printing only), and UpdateRateAfterAllowedWidth (every group here
// fits the channel).
#include "mac_phy_sim/minstrel_ht.h"

#include <algorithm>
#include <utility>

#include "mac_phy_sim/minstrel.h"

namespace sitlnet::mac {
namespace {

// CalculateRetransmits: the longest retry count whose expected time stays within 6 ms.
constexpr TimeNs kRetryChainBudgetNs = 6 * kNsPerMs;

int WidthIndex(int channel_width_mhz) {
  switch (channel_width_mhz) {
    case 160: return 3;
    case 80: return 2;
    case 40: return 1;
    default: return 0;
  }
}

}  // namespace

int MinstrelHtGroupId(int streams, bool short_guard_interval, int channel_width_mhz) {
  return 4 * 2 * WidthIndex(channel_width_mhz) + 4 * (short_guard_interval ? 1 : 0) + streams - 1;
}

int MinstrelVhtGroupId(int streams, bool short_guard_interval, int channel_width_mhz) {
  return kMinstrelHtGroups + 8 * 2 * WidthIndex(channel_width_mhz) +
         8 * (short_guard_interval ? 1 : 0) + streams - 1;
}

MinstrelHt::MinstrelHt(MinstrelHtPhy phy, const MediumConfig::Minstrel& config, uint64_t seed)
    : phy_(std::move(phy)), config_(config), rng_(seed) {
  // ns-3's RateInit: "No supported group has been found" is fatal.
  SITLNET_DEMAND(std::any_of(phy_.groups.begin(), phy_.groups.end(),
                             [](const MinstrelHtGroup& g) { return g.supported; }));
}

MinstrelHtRemote MinstrelHt::NewRemote(TimeNs now_ns) {
  MinstrelHtRemote r;
  r.next_stats_update_ns = now_ns + config_.ht_update_stats_ns;
  const int groups = static_cast<int>(phy_.groups.size());
  const int n = phy_.rates_per_group;
  // InitSampleTable: one table of rate ids for all groups.
  r.sample_table.assign(n, std::vector<int>(config_.sample_columns, 0));
  FillSampleTable(rng_, r.sample_table);
  // RateInit.
  r.groups.resize(groups);
  r.rates.resize(static_cast<size_t>(groups) * n);
  for (int g = 0; g < groups; ++g) {
    const MinstrelHtGroup& group = phy_.groups[g];
    if (!group.supported) continue;
    for (int i = 0; i < n; ++i) {
      if (!group.rate_supported[i]) continue;
      MinstrelHtRateStats& rate = r.rates[Index(g, i)];
      rate.supported = true;
      rate.perfect_tx_ns = group.first_mpdu_ns[i];
      CalculateRetransmits(r, Index(g, i));
    }
  }
  SetNextSample(r);  // The first group to sample.
  UpdateStats(r, now_ns);
  r.tx_rate = FindRate(r);
  return r;
}

void MinstrelHt::CalculateRetransmits(MinstrelHtRemote& r, int index) const {
  MinstrelHtRateStats& rate = r.rates[index];
  if (rate.retry_updated) return;
  if (rate.ewma_probability < 1) {
    rate.retry_count = 1;
    return;
  }
  rate.retry_count = 2;
  rate.retry_updated = true;
  const MinstrelHtGroup& group = phy_.groups[GroupOf(index)];
  // An A-MPDU of the average length: the first MPDU, then avg - 1 middle ones.
  const TimeNs data_ns = group.first_mpdu_ns[RateOf(index)] +
                         group.middle_mpdu_ns[RateOf(index)] * (r.avg_ampdu_len - 1);
  const TimeNs ack_ns = phy_.sifs_ns + phy_.block_ack_tx_ns;
  // ns-3's contention approximation: CW from 15, (cw + 1) x 2 per try up to 1023, half of it
  // in slots (integer halves).
  int cw = 15;
  TimeNs cw_ns = (cw / 2) * phy_.slot_ns;
  cw = std::min((cw + 1) * 2, 1023);
  cw_ns += (cw / 2) * phy_.slot_ns;
  cw = std::min((cw + 1) * 2, 1023);
  TimeNs tx_ns = cw_ns + 2 * (data_ns + ack_ns);  // The first two tries.
  do {
    cw_ns = (cw / 2) * phy_.slot_ns;
    cw = std::min((cw + 1) * 2, 1023);
    tx_ns += cw_ns + ack_ns + data_ns;
  } while (tx_ns < kRetryChainBudgetNs && ++rate.retry_count < 7);
}

// The retry chain (ns-3's table in UpdateRate; Linux's lowest rate is not used). Not sampling:
// best throughput, second best, best probability, each for its retry count. Sampling (the
// sample went first, once): second best, then best probability. ns-3 counts the second best's
// retries in the best rate's group there; kept.
void MinstrelHt::UpdateRate(MinstrelHtRemote& r) const {
  ++r.long_retry;
  const uint32_t tp = r.rates[r.max_tp_rate].retry_count;
  const uint32_t tp2 = r.rates[r.max_tp_rate2].retry_count;
  const uint32_t prob = r.rates[r.max_prob_rate].retry_count;
  if (!r.is_sampling) {
    if (r.long_retry < tp) {
      r.tx_rate = r.max_tp_rate;
    } else if (r.long_retry < tp + tp2) {
      r.tx_rate = r.max_tp_rate2;
    } else {
      // ns-3: NS_FATAL_ERROR past the chain ("m_longRetry not cleared properly").
      SITLNET_DEMAND(r.long_retry <= tp + tp2 + prob);
      r.tx_rate = r.max_prob_rate;
    }
    return;
  }
  const uint32_t tp2_in_tp_group =
      r.rates[Index(GroupOf(r.max_tp_rate), RateOf(r.max_tp_rate2))].retry_count;
  if (r.long_retry < 1 + tp2_in_tp_group) {
    r.tx_rate = r.max_tp_rate2;
  } else {
    SITLNET_DEMAND(r.long_retry <= 1 + tp2_in_tp_group + prob);
    r.tx_rate = r.max_prob_rate;
  }
}

uint32_t MinstrelHt::CountRetries(const MinstrelHtRemote& r) const {
  const uint32_t prob = r.rates[r.max_prob_rate].retry_count;
  if (!r.is_sampling) {
    return r.rates[r.max_tp_rate].retry_count + r.rates[r.max_tp_rate2].retry_count + prob;
  }
  return 1 + r.rates[Index(GroupOf(r.max_tp_rate), RateOf(r.max_tp_rate2))].retry_count + prob;
}

void MinstrelHt::ReportDataFailed(MinstrelHtRemote& r) const {
  if (r.long_retry >= CountRetries(r)) return;
  ++r.rates[r.tx_rate].attempts;
  UpdateRate(r);
}

void MinstrelHt::ReportDataOk(MinstrelHtRemote& r, TimeNs now_ns) const {
  ++r.rates[r.tx_rate].successes;
  ++r.rates[r.tx_rate].attempts;
  UpdatePacketCounters(r, 1, 0);
  AfterFrame(r, now_ns);
}

void MinstrelHt::ReportFinalDataFailed(MinstrelHtRemote& r, TimeNs now_ns) const {
  UpdatePacketCounters(r, 0, 1);
  AfterFrame(r, now_ns);
}

void MinstrelHt::ReportAmpduTxStatus(MinstrelHtRemote& r, int mpdus_ok, int mpdus_failed,
                                     TimeNs now_ns) const {
  ++r.ampdu_packet_count;
  r.ampdu_len += static_cast<uint32_t>(mpdus_ok + mpdus_failed);
  UpdatePacketCounters(r, mpdus_ok, mpdus_failed);
  // ns-3 credits the rate of the next attempt (m_txrate), which is the A-MPDU's.
  MinstrelHtRateStats& rate = r.rates[r.tx_rate];
  rate.successes += static_cast<uint32_t>(mpdus_ok);
  rate.attempts += static_cast<uint32_t>(mpdus_ok + mpdus_failed);
  if (mpdus_ok == 0 && r.long_retry < CountRetries(r)) {
    UpdateRate(r);  // No BlockAck: the whole A-MPDU failed.
    return;
  }
  AfterFrame(r, now_ns);
}

// What DoReportDataOk, DoReportFinalDataFailed and a delivered A-MPDU end with.
void MinstrelHt::AfterFrame(MinstrelHtRemote& r, TimeNs now_ns) const {
  r.is_sampling = false;
  UpdateRetry(r);
  if (now_ns >= r.next_stats_update_ns) UpdateStats(r, now_ns);
  r.tx_rate = FindRate(r);
}

void MinstrelHt::UpdatePacketCounters(MinstrelHtRemote& r, int mpdus_ok, int mpdus_failed) {
  const auto mpdus = static_cast<uint32_t>(mpdus_ok + mpdus_failed);
  r.total_packets += mpdus;
  if (r.is_sampling) r.sample_packets += mpdus;
  if (r.total_packets == ~uint32_t{0}) r.total_packets = r.sample_packets = 0;
  // A new sample is due after 16 + 2 x (average A-MPDU length) frames, while the interval's
  // sample budget lasts.
  if (r.sample_wait == 0 && r.sample_tries == 0 && r.sample_count > 0) {
    r.sample_wait = 16 + 2 * r.avg_ampdu_len;
    r.sample_tries = 1;
    --r.sample_count;
  }
}

int MinstrelHt::NextSample(MinstrelHtRemote& r) const {
  const MinstrelHtRemote::GroupCursor& cursor = r.groups[r.sample_group];
  const int rate_index = Index(r.sample_group, r.sample_table[cursor.index][cursor.column]);
  SetNextSample(r);
  return rate_index;
}

// The next supported group (round robin over ns-3's group ids) moves one row down its column.
void MinstrelHt::SetNextSample(MinstrelHtRemote& r) const {
  const int groups = static_cast<int>(phy_.groups.size());
  do {
    r.sample_group = (r.sample_group + 1) % groups;
  } while (!phy_.groups[r.sample_group].supported);
  MinstrelHtRemote::GroupCursor& cursor = r.groups[r.sample_group];
  if (++cursor.index >= phy_.rates_per_group) {
    cursor.index = 0;
    if (++cursor.column >= config_.sample_columns) cursor.column = 0;
  }
}

int MinstrelHt::FindRate(MinstrelHtRemote& r) const {
  if (r.sample_packets + r.total_packets == 0) return r.max_tp_rate;
  if (r.sample_wait == 0 && r.sample_tries != 0) {
    const int sample = NextSample(r);
    const MinstrelHtRateStats& info = r.rates[sample];
    // Not a rate of the chain already, not one above 95 %, and not an unsupported MCS.
    if (info.supported && sample != r.max_tp_rate && sample != r.max_tp_rate2 &&
        sample != r.max_prob_rate && info.ewma_probability <= 95) {
      // A rate slower than the second best is sampled only if it uses fewer streams than the
      // best and beats the best-probability rate, or rarely (skipped 20 updates, twice per
      // update at most).
      const int sample_streams = phy_.groups[GroupOf(sample)].streams;
      const int max_tp_streams = phy_.groups[GroupOf(r.max_tp_rate)].streams;
      const bool faster =
          info.perfect_tx_ns < r.rates[r.max_tp_rate2].perfect_tx_ns ||
          (sample_streams < max_tp_streams &&
           info.perfect_tx_ns < r.rates[r.max_prob_rate].perfect_tx_ns);
      bool take = faster;
      if (!faster) {
        ++r.samples_slow;
        take = info.samples_skipped >= 20 && r.samples_slow <= 2;
      }
      if (take) {
        r.is_sampling = true;
        r.sample_rate = sample;
        --r.sample_tries;
        return sample;
      }
    }
  }
  if (r.sample_wait > 0) --r.sample_wait;
  return r.max_tp_rate;
}

void MinstrelHt::UpdateStats(MinstrelHtRemote& r, TimeNs now_ns) const {
  r.next_stats_update_ns = now_ns + config_.ht_update_stats_ns;
  r.samples_slow = 0;
  r.sample_count = 0;
  const int ewma = config_.ewma_percent;
  if (r.ampdu_packet_count > 0) {
    const uint32_t new_len = r.ampdu_len / r.ampdu_packet_count;
    r.avg_ampdu_len = (new_len * (100 - ewma) + r.avg_ampdu_len * ewma) / 100;
    r.ampdu_len = r.ampdu_packet_count = 0;
  }
  r.max_tp_rate = r.max_tp_rate2 = r.max_prob_rate = LowestIndex(r);
  const int groups = static_cast<int>(phy_.groups.size());
  for (int g = 0; g < groups; ++g) {
    if (!phy_.groups[g].supported) continue;
    ++r.sample_count;
    for (int i = 0; i < phy_.rates_per_group; ++i) {
      const int index = Index(g, i);
      MinstrelHtRateStats& rate = r.rates[index];
      if (!rate.supported) continue;
      rate.retry_updated = false;
      if (rate.attempts > 0) {
        rate.samples_skipped = 0;
        // Whole percent (ns-3 divides integers, then keeps the EWMA in a double).
        double probability = static_cast<double>(100 * rate.successes / rate.attempts);
        rate.probability = probability;
        if (rate.success_history == 0) {
          rate.ewma_probability = probability;
        } else {
          probability = (probability * (100 - ewma) + rate.ewma_probability * ewma) / 100;
          rate.ewma_probability = probability;
        }
        // CalculateThroughput: nothing below 10 %, the probability capped at 90 %.
        const double seconds = static_cast<double>(rate.perfect_tx_ns) / 1e9;  // GetSeconds.
        rate.throughput = probability < 10 ? 0 : std::min(probability, 90.0) / seconds;
        rate.success_history += rate.successes;
        rate.attempt_history += rate.attempts;
      } else {
        ++rate.samples_skipped;
      }
      rate.previous_successes = rate.successes;
      rate.previous_attempts = rate.attempts;
      rate.successes = rate.attempts = 0;
      if (rate.throughput != 0) {
        SetBestStationThRates(r, index);
        SetBestProbabilityRate(r, index);
      }
    }
  }
  r.sample_count *= 8;  // Try to sample every rate once per interval.
  CalculateRetransmits(r, r.max_tp_rate);
  CalculateRetransmits(r, r.max_tp_rate2);
  CalculateRetransmits(r, r.max_prob_rate);
}

// The two best throughputs; equal throughputs go to the more probable rate.
void MinstrelHt::SetBestStationThRates(MinstrelHtRemote& r, int index) const {
  const MinstrelHtRateStats& rate = r.rates[index];
  const MinstrelHtRateStats& best = r.rates[r.max_tp_rate];
  const MinstrelHtRateStats& second = r.rates[r.max_tp_rate2];
  if (rate.throughput > best.throughput ||
      (rate.throughput == best.throughput && rate.ewma_probability > best.ewma_probability)) {
    r.max_tp_rate2 = r.max_tp_rate;
    r.max_tp_rate = index;
  } else if (rate.throughput > second.throughput ||
             (rate.throughput == second.throughput &&
              rate.ewma_probability > second.ewma_probability)) {
    r.max_tp_rate2 = index;
  }
}

// Above 75 %: the fastest such rate; else the most probable.
void MinstrelHt::SetBestProbabilityRate(MinstrelHtRemote& r, int index) const {
  const MinstrelHtRateStats& rate = r.rates[index];
  const MinstrelHtRateStats& current = r.rates[r.max_prob_rate];
  if (rate.ewma_probability > 75) {
    if (rate.throughput > current.throughput) r.max_prob_rate = index;
  } else if (rate.ewma_probability > current.ewma_probability) {
    r.max_prob_rate = index;
  }
}

int MinstrelHt::LowestIndex(const MinstrelHtRemote& r) const {
  int g = 0;
  while (!phy_.groups[g].supported) ++g;
  int i = 0;
  while (!r.rates[Index(g, i)].supported) ++i;
  return Index(g, i);
}

}  // namespace sitlnet::mac

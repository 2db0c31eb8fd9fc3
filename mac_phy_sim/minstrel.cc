// ns-3 3.37's MinstrelWifiManager, function by function (names as there), with
// its integer arithmetic and its quirks kept, so both pick the same rates.
#include "mac_phy_sim/minstrel.h"

#include <algorithm>

namespace sitlnet::mac {
namespace {

// ns-3 scales probabilities to 18000 (100 % x 180).
constexpr uint32_t kProbabilityScale = 18000;
// RateInit: the longest retry chain per rate whose expected time stays within 6 ms.
constexpr TimeNs kRetryChainBudgetNs = 6 * kNsPerMs;

}  // namespace

// By multiply-shift: no division, the same value on every library version.
int UniformInclusive(std::mt19937_64& rng, int max_inclusive) {
  return static_cast<int>((static_cast<unsigned __int128>(rng()) *
                           static_cast<uint64_t>(max_inclusive + 1)) >>
                          64);
}

void FillSampleTable(std::mt19937_64& rng, std::vector<std::vector<int>>& table) {
  const int n = static_cast<int>(table.size());
  const int columns = n == 0 ? 0 : static_cast<int>(table.front().size());
  for (int col = 0; col < columns; ++col) {
    for (int i = 0; i < n; ++i) {
      int new_index = (i + UniformInclusive(rng, n)) % n;
      while (table[new_index][col] != 0) new_index = (new_index + 1) % n;
      table[new_index][col] = i;
    }
  }
}

Minstrel::Minstrel(MinstrelPhy phy, const MediumConfig::Minstrel& config, uint64_t seed)
    : phy_(std::move(phy)), config_(config), rng_(seed) {
  SITLNET_DEMAND(phy_.perfect_tx_ns.size() >= 2);  // ns-3's CheckInit: more than one mode.
}

TimeNs Minstrel::UnicastTimeNs(TimeNs data_ns, uint32_t long_retries) const {
  // ns-3's CalculateTimeUnicastPacket (after rc80211_minstrel.c): the first attempt, then per
  // retry another attempt and half the contention window of backoff, CW 31 doubling to 1023.
  const TimeNs attempt_ns = data_ns + phy_.sifs_ns + phy_.ack_tx_ns;
  TimeNs total_ns = attempt_ns;
  int cw = 31;
  for (uint32_t retry = 0; retry < long_retries; ++retry) {
    total_ns += attempt_ns + cw * phy_.slot_ns / 2;
    cw = std::min(1023, (cw + 1) * 2);
  }
  return total_ns;
}

MinstrelRemote Minstrel::NewRemote(TimeNs now_ns) {
  MinstrelRemote r;
  r.next_stats_update_ns = now_ns + config_.update_stats_ns;
  const int n = rate_count();
  r.rates.resize(n);
  r.sample_table.assign(n, std::vector<int>(config_.sample_columns, 0));
  InitSampleTable(r);
  // RateInit.
  for (int i = 0; i < n; ++i) {
    MinstrelRateStats& rate = r.rates[i];
    rate.perfect_tx_ns = phy_.perfect_tx_ns[i];
    for (uint32_t retries = 2; retries < 11; ++retries) {
      if (UnicastTimeNs(rate.perfect_tx_ns, retries) > kRetryChainBudgetNs) break;
      rate.sample_limit = -1;
      rate.retry_count = rate.adjusted_retry_count = retries;
    }
  }
  return r;
}

void Minstrel::InitSampleTable(MinstrelRemote& r) {
  r.column = r.index = 0;
  FillSampleTable(rng_, r.sample_table);
}

// The retry chain (ns-3's table in UpdateRate): three stages of adjusted_retry_count attempts
// each, then the lowest rate. Not sampling: best, second best throughput, best probability.
// Sampling a slower rate (deferred): best, sample, best probability. A faster one: sample,
// best, best probability.
void Minstrel::UpdateRate(MinstrelRemote& r) const {
  ++r.long_retry;
  ++r.rates[r.tx_rate].attempts;
  int stages[3] = {r.max_tp_rate, r.max_tp_rate2, r.max_prob_rate};
  if (r.is_sampling) {
    stages[0] = r.sample_deferred ? r.max_tp_rate : r.sample_rate;
    stages[1] = r.sample_deferred ? r.sample_rate : r.max_tp_rate;
  }
  const uint32_t first = r.rates[stages[0]].adjusted_retry_count;
  const uint32_t second = first + r.rates[stages[1]].adjusted_retry_count;
  const uint32_t third = second + r.rates[stages[2]].adjusted_retry_count;
  if (r.long_retry < first) {
    r.tx_rate = stages[0];
  } else if (r.long_retry <= second) {
    r.tx_rate = stages[1];
  } else if (r.long_retry <= third) {
    r.tx_rate = stages[2];
  } else {
    r.tx_rate = 0;
  }
}

uint32_t Minstrel::CountRetries(const MinstrelRemote& r) {
  const int first = r.is_sampling ? r.sample_rate : r.max_tp_rate;
  const int second = r.is_sampling ? r.max_tp_rate : r.max_tp_rate2;
  return r.rates[first].adjusted_retry_count + r.rates[second].adjusted_retry_count +
         r.rates[r.max_prob_rate].adjusted_retry_count + r.rates[0].adjusted_retry_count;
}

int Minstrel::NextSample(MinstrelRemote& r) const {
  const int rate = r.sample_table[r.index][r.column];
  ++r.index;
  if (r.index > rate_count() - 2) {
    r.index = 0;
    if (++r.column >= config_.sample_columns) r.column = 0;
  }
  return rate;
}

int Minstrel::FindRate(MinstrelRemote& r) const {
  if (r.total_packets == 0) return 0;
  const int delta = r.total_packets * config_.look_around_percent / 100 -
                    (r.sample_packets + r.samples_deferred / 2);
  if (delta < 0) return r.max_tp_rate;  // No sampling due.
  const int n = rate_count();
  // Linux: with too large a sampling backlog a worsening link would burst out samples.
  if (delta > n * 2) r.sample_packets += delta - n * 2;
  int rate = NextSample(r);
  r.sample_rate = rate;
  MinstrelRateStats& sample = r.rates[rate];
  // Linux: a rate slower than the best goes second in the chain (deferred), unless it has
  // been skipped for 20 updates.
  if (sample.perfect_tx_ns > r.rates[r.max_tp_rate].perfect_tx_ns &&
      sample.samples_skipped < 20) {
    r.sample_deferred = true;
    ++r.samples_deferred;
    r.is_sampling = true;
  } else if (sample.sample_limit == 0) {
    rate = r.max_tp_rate;
    r.is_sampling = false;
  } else {
    r.is_sampling = true;
    if (sample.sample_limit > 0) --sample.sample_limit;
  }
  if (r.sample_deferred) rate = r.max_tp_rate;
  return rate;
}

void Minstrel::UpdatePacketCounters(MinstrelRemote& r) {
  ++r.total_packets;
  if (r.is_sampling &&
      (!r.sample_deferred || r.long_retry >= r.rates[r.max_tp_rate].adjusted_retry_count)) {
    ++r.sample_packets;
  }
  if (r.samples_deferred > 0) --r.samples_deferred;
  r.is_sampling = false;
  r.sample_deferred = false;
}

void Minstrel::UpdateRetry(MinstrelRemote& r) {
  r.retry = r.short_retry + r.long_retry;
  r.short_retry = r.long_retry = 0;
}

void Minstrel::ReportDataOk(MinstrelRemote& r, TimeNs now_ns) const {
  ++r.rates[r.tx_rate].successes;
  ++r.rates[r.tx_rate].attempts;
  UpdatePacketCounters(r);
  UpdateRetry(r);
  UpdateStats(r, now_ns);
  r.tx_rate = FindRate(r);
}

void Minstrel::ReportFinalDataFailed(MinstrelRemote& r, TimeNs now_ns) const {
  UpdatePacketCounters(r);
  UpdateRetry(r);
  UpdateStats(r, now_ns);
  r.tx_rate = FindRate(r);
}

void Minstrel::UpdateStats(MinstrelRemote& r, TimeNs now_ns) const {
  if (now_ns < r.next_stats_update_ns) return;
  r.next_stats_update_ns = now_ns + config_.update_stats_ns;
  for (MinstrelRateStats& rate : r.rates) {
    // ns-3 divides in whole microseconds (Time::GetMicroSeconds truncates).
    int64_t tx_us = rate.perfect_tx_ns / kNsPerUs;
    if (tx_us == 0) tx_us = 1000000;
    if (rate.attempts > 0) {
      rate.samples_skipped = 0;
      uint32_t probability = rate.successes * kProbabilityScale / rate.attempts;
      rate.probability = probability;
      if (rate.success_history == 0) {
        rate.ewma_probability = probability;
      } else {
        probability = (probability * (100 - config_.ewma_percent) +
                       rate.ewma_probability * config_.ewma_percent) /
                      100;
        rate.ewma_probability = probability;
      }
      rate.throughput = probability * static_cast<uint32_t>(1000000 / tx_us);
    } else {
      ++rate.samples_skipped;
    }
    rate.success_history += rate.successes;
    rate.attempt_history += rate.attempts;
    rate.previous_successes = rate.successes;
    rate.previous_attempts = rate.attempts;
    rate.successes = rate.attempts = 0;
    // Below 10 % and above 95 % success: at most 2 tries, at most 4 samples.
    if (rate.ewma_probability > 17100 || rate.ewma_probability < 1800) {
      if (rate.retry_count > 2) rate.adjusted_retry_count = 2;
      rate.sample_limit = 4;
    } else {
      rate.sample_limit = -1;
      rate.adjusted_retry_count = rate.retry_count;
    }
    if (rate.adjusted_retry_count == 0) rate.adjusted_retry_count = 2;
  }
  // Best and second-best throughput (first index wins ties), then the best probability: the
  // fastest rate above 95 %, else the most probable (the last index wins ties).
  const int n = rate_count();
  uint32_t max_tp = 0;
  int index_max_tp = 0, index_max_tp2 = 0;
  for (int i = 0; i < n; ++i) {
    if (max_tp < r.rates[i].throughput) {
      index_max_tp = i;
      max_tp = r.rates[i].throughput;
    }
  }
  max_tp = 0;
  for (int i = 0; i < n; ++i) {
    if (i != index_max_tp && max_tp < r.rates[i].throughput) {
      index_max_tp2 = i;
      max_tp = r.rates[i].throughput;
    }
  }
  uint32_t max_prob = 0;
  int index_max_prob = 0;
  for (int i = 0; i < n; ++i) {
    if (r.rates[i].ewma_probability >= 95 * 180 &&
        r.rates[i].throughput >= r.rates[index_max_prob].throughput) {
      index_max_prob = i;
      max_prob = r.rates[i].ewma_probability;
    } else if (r.rates[i].ewma_probability >= max_prob) {
      index_max_prob = i;
      max_prob = r.rates[i].ewma_probability;
    }
  }
  r.max_tp_rate = index_max_tp;
  r.max_tp_rate2 = index_max_tp2;
  r.max_prob_rate = index_max_prob;
  // ns-3 compares indices here, not throughputs.
  if (index_max_tp > r.tx_rate) r.tx_rate = index_max_tp;
}

}  // namespace sitlnet::mac

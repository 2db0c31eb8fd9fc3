// Minstrel-HT (minstrel_ht.h) as a station's RateManager: ns-3's groups built
// from the config (the station and its destinations support the same: every
// width up to the channel's, the long GI and the short one if enabled, 1 to
// the config's spatial streams; HT groups on 802.11n, VHT groups only on
// 802.11ac, as ns-3's UseLatestAmendmentOnly), per-destination state made at
// first use, and the indices it picks mapped to the medium's rate table.
#include <utility>
#include <vector>

#include "mac_phy_sim/medium_state.h"
#include "mac_phy_sim/minstrel_family_rate_manager.h"
#include "mac_phy_sim/minstrel_ht.h"

namespace sitlnet::mac {
namespace {

// ns-3's WifiPhy::GetBlockAckTxTime (Configure80211n, 802.11-2016 Table 10-5).
constexpr TimeNs kBlockAckTxNs = 68 * kNsPerUs;

class MinstrelHtRateManager final
    : public MinstrelFamilyRateManager<MinstrelHt, MinstrelHtRemote> {
 public:
  MinstrelHtRateManager(std::vector<const RateEntry*> by_index, MinstrelHt minstrel)
      : MinstrelFamilyRateManager(std::move(minstrel)), by_index_(std::move(by_index)) {}

  TxRates Choose(const MacAddress& destination, TimeNs now_ns) override {
    const RateEntry* data = by_index_[Remote(destination, now_ns).tx_rate];
    SITLNET_DEMAND(data != nullptr);
    // ns-3's DoGetRtsTxVector: the highest basic rate not above the MCS's non-HT reference
    // rate, which is the control rate of the entry (phy_mode.h).
    return TxRates{data, data, &data->control};
  }

 private:
  std::vector<const RateEntry*> by_index_;  // Into State::rates; null: no such rate.
};

// The group of `group_id` (ns-3's numbering) with its rates, or an unsupported one.
MinstrelHtGroup MakeGroup(const State& s, int group_id, int rates_per_group,
                          std::vector<const RateEntry*>& by_index) {
  const MediumConfig& config = s.config;
  const PhyMode data = DataModeFor(config, StationRadio{});
  const bool vht = data.format == PhyFormat::kVht;
  MinstrelHtGroup group;
  // Decode the id: HT ids count streams 1-4, VHT ids 1-8, then GI, then width.
  const bool vht_group = group_id >= kMinstrelHtGroups;
  const int local = vht_group ? group_id - kMinstrelHtGroups : group_id;
  const int streams_per_gi = vht_group ? 8 : 4;
  group.streams = local % streams_per_gi + 1;
  const bool short_gi = (local / streams_per_gi) % 2 == 1;
  const int width_mhz = 20 << (local / (2 * streams_per_gi));
  group.supported = vht_group == vht && (!short_gi || data.short_guard_interval) &&
                    width_mhz <= data.channel_width_mhz && group.streams <= data.spatial_streams;
  if (!group.supported) return group;
  group.rate_supported.assign(rates_per_group, false);
  group.first_mpdu_ns.assign(rates_per_group, 0);
  group.middle_mpdu_ns.assign(rates_per_group, 0);
  for (int rate = 0; rate < rates_per_group; ++rate) {
    if (!vht && rate >= 8) continue;
    const int mcs = vht ? rate : (group.streams - 1) * 8 + rate;
    PhyMode mode;
    try {
      mode = McsModeFor(config.standard, mcs, group.streams, width_mhz, short_gi);
    } catch (const Error&) {
      continue;  // VHT MCS 9 at 20 MHz with 1 or 2 streams: no such mode (ns-3's IsValidMcs).
    }
    group.rate_supported[rate] = true;
    // ns-3 times the groups with the HT-mixed preamble type, which VhtPhy times as its own.
    const PhyHeader header = HeaderFor(config.standard, mode, false);
    const int bytes = config.minstrel.packet_bytes;
    group.first_mpdu_ns[rate] = AmpduMpduDurationNs(mode, header, bytes, true);
    group.middle_mpdu_ns[rate] = AmpduMpduDurationNs(mode, header, bytes, false);
    by_index[static_cast<size_t>(group_id) * rates_per_group + rate] = &RateFor(s, mode);
  }
  return group;
}

}  // namespace

std::unique_ptr<RateManager> MakeMinstrelHtRateManager(const State& s, uint64_t seed) {
  const bool vht = DataModeFor(s.config, StationRadio{}).format == PhyFormat::kVht;
  MinstrelHtPhy phy;
  // ns-3's DoInitialize: 8 rates per group and the HT groups; a VHT PHY adds its groups and
  // makes it 10 rates per group.
  phy.rates_per_group = vht ? 10 : 8;
  const int groups = kMinstrelHtGroups + (vht ? kMinstrelVhtGroups : 0);
  std::vector<const RateEntry*> by_index(static_cast<size_t>(groups) * phy.rates_per_group,
                                         nullptr);
  for (int g = 0; g < groups; ++g) {
    phy.groups.push_back(MakeGroup(s, g, phy.rates_per_group, by_index));
  }
  phy.slot_ns = s.phy.slot_ns;
  phy.sifs_ns = s.phy.sifs_ns;
  phy.block_ack_tx_ns = kBlockAckTxNs;
  return std::make_unique<MinstrelHtRateManager>(
      std::move(by_index), MinstrelHt(std::move(phy), s.config.minstrel, seed));
}

}  // namespace sitlnet::mac

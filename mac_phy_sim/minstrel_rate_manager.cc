// Minstrel (minstrel.h) as a station's RateManager: its supported-mode list
// in ns-3's order, per-destination state created at first use, and the
// indices it picks mapped to the medium's rate table.
#include <utility>
#include <vector>

#include "mac_phy_sim/medium_state.h"
#include "mac_phy_sim/minstrel.h"
#include "mac_phy_sim/minstrel_family_rate_manager.h"

namespace sitlnet::mac {
namespace {

// ns-3 3.37's WifiPhy::GetModeList: the modes of each PHY entity, by modulation class (DSSS,
// HR/DSSS, ERP-OFDM, OFDM). 802.11b registers its one DSSS entity, which holds 1, 2, 5.5 and
// 11 Mb/s, under both DSSS and HR/DSSS, so 11b and 11g list those four rates twice: an ad hoc
// destination's supported set (AddAllSupportedModes) and Minstrel's table have them twice.
std::vector<double> SupportedRatesMbps(Standard standard) {
  const std::vector<double> dsss = {1, 2, 5.5, 11};
  const std::vector<double> ofdm = {6, 9, 12, 18, 24, 36, 48, 54};
  std::vector<double> rates;
  if (standard == Standard::k80211b || standard == Standard::k80211g) {
    for (int entity = 0; entity < 2; ++entity) rates.insert(rates.end(), dsss.begin(), dsss.end());
  }
  if (standard != Standard::k80211b) rates.insert(rates.end(), ofdm.begin(), ofdm.end());
  return rates;
}

// ns-3's WifiPhy::GetAckTxTime (Configure80211a / Configure80211b; 11g configures 11b first).
TimeNs AckTxTimeNs(Standard standard) {
  return (standard == Standard::k80211a ? 44 : 304) * kNsPerUs;
}

class MinstrelRateManager final
    : public MinstrelFamilyRateManager<Minstrel, MinstrelRemote> {
 public:
  MinstrelRateManager(std::vector<const RateEntry*> supported, Minstrel minstrel)
      : MinstrelFamilyRateManager(std::move(minstrel)), supported_(std::move(supported)) {}

  TxRates Choose(const MacAddress& destination, TimeNs now_ns) override {
    const RateEntry* data = supported_[Remote(destination, now_ns).tx_rate];
    // ns-3's GetRtsTxVector: the first supported mode.
    return TxRates{data, supported_.front(), &supported_.front()->data};
  }

 private:
  std::vector<const RateEntry*> supported_;  // Into State::rates (never resized).
};

}  // namespace

std::unique_ptr<RateManager> MakeMinstrelRateManager(const State& s, uint64_t seed) {
  const MediumConfig& config = s.config;
  std::vector<const RateEntry*> supported;
  MinstrelPhy phy;
  for (double rate_mbps : SupportedRatesMbps(config.standard)) {
    const RateEntry& entry = RateFor(s, ModeFor(config.standard, rate_mbps));
    supported.push_back(&entry);
    // ns-3's SetupPhy: the TX time of PacketLength bytes with the long preamble.
    const PhyMode& mode = entry.data.mode;
    phy.perfect_tx_ns.push_back(
        PpduDurationNs(mode, HeaderFor(config.standard, mode, false), config.minstrel.packet_bytes));
  }
  phy.sifs_ns = s.phy.sifs_ns;
  phy.slot_ns = s.phy.slot_ns;
  phy.ack_tx_ns = AckTxTimeNs(config.standard);
  return std::make_unique<MinstrelRateManager>(std::move(supported),
                                               Minstrel(std::move(phy), config.minstrel, seed));
}

}  // namespace sitlnet::mac

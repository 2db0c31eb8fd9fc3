#include "scenario/radio_standard.h"

#include <sstream>

#include "mac_phy_sim/phy_mode.h"

namespace sitlnet {
namespace {

std::string SpacedRates(mac::Standard standard) {
  std::ostringstream text;
  for (double rate : mac::RatesMbps(standard)) text << (text.tellp() > 0 ? " " : "") << rate;
  return text.str();
}

}  // namespace

mac::Standard MacStandard(proto::Radio::Standard standard) {
  switch (standard) {
    case proto::Radio::STANDARD_80211B:
      return mac::Standard::k80211b;
    case proto::Radio::STANDARD_80211G:
      return mac::Standard::k80211g;
    case proto::Radio::STANDARD_80211N_2_4GHZ:
      return mac::Standard::k80211n2_4GHz;
    case proto::Radio::STANDARD_80211N_5GHZ:
      return mac::Standard::k80211n5GHz;
    case proto::Radio::STANDARD_80211AC:
      return mac::Standard::k80211ac;
    default:
      return mac::Standard::k80211a;
  }
}

bool IsRateOf(proto::Radio::Standard standard, double rate_mbps) {
  return mac::HasRate(MacStandard(standard), rate_mbps);
}

bool IsHtOrVht(proto::Radio::Standard standard) { return mac::IsHtOrVht(MacStandard(standard)); }

std::string McsProblem(const proto::Radio& radio, uint32_t mcs) {
  mac::MediumConfig config;
  config.standard = MacStandard(radio.standard());
  config.mcs = static_cast<int>(mcs);
  if (radio.has_spatial_streams()) config.spatial_streams = static_cast<int>(radio.spatial_streams());
  if (radio.has_channel_width_mhz()) {
    config.channel_width_mhz = static_cast<int>(radio.channel_width_mhz());
  }
  config.short_guard_interval = radio.short_guard_interval();
  try {
    mac::DataModeFor(config, mac::StationRadio{});
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string RateListsText() {
  // 802.11g's list is both of the others (an ERP PHY has the DSSS rates): said as "both".
  return " (802.11a: " + SpacedRates(mac::Standard::k80211a) +
         "; 802.11b: " + SpacedRates(mac::Standard::k80211b) + "; 802.11g: both)";
}

}  // namespace sitlnet

#include "scenario/radio_standard.h"

#include <sstream>

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
    default:
      return mac::Standard::k80211a;
  }
}

bool IsRateOf(proto::Radio::Standard standard, double rate_mbps) {
  return mac::HasRate(MacStandard(standard), rate_mbps);
}

std::string RateListsText() {
  // 802.11g's list is both of the others (an ERP PHY has the DSSS rates): said as "both".
  return " (802.11a: " + SpacedRates(mac::Standard::k80211a) +
         "; 802.11b: " + SpacedRates(mac::Standard::k80211b) + "; 802.11g: both)";
}

}  // namespace sitlnet

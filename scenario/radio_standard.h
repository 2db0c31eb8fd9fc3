// The scenario's radio standard in mac_phy_sim's terms, and its data rates: validation and the
// medium adapter both read mac_phy_sim's one table of PHY modes through here.
#ifndef SITLNET_SCENARIO_RADIO_STANDARD_H_
#define SITLNET_SCENARIO_RADIO_STANDARD_H_

#include <string>

#include "mac_phy_sim/mac_phy_sim.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet {

// mac_phy_sim's Standard for the scenario's Radio.standard.
mac::Standard MacStandard(proto::Radio::Standard standard);

// True if `rate_mbps` is a data rate of `standard` (mac::RatesMbps).
bool IsRateOf(proto::Radio::Standard standard, double rate_mbps);

// True for 802.11n and 802.11ac (data at an MCS, QoS stations).
bool IsHtOrVht(proto::Radio::Standard standard);

// Empty if `mcs` is a valid data mode with the radio's streams, width and guard interval, else why
// not (mac::McsModeFor's message, naming the field).
std::string McsProblem(const proto::Radio& radio, uint32_t mcs);

// The rates of every standard for a message:
// " (802.11a: 6 9 12 18 24 36 48 54; 802.11b: 1 2 5.5 11; 802.11g: both)".
std::string RateListsText();

}  // namespace sitlnet

#endif  // SITLNET_SCENARIO_RADIO_STANDARD_H_

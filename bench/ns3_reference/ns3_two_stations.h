// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Two ad hoc 802.11a stations in ns-3 3.37 on the matrix's channel, for the
// TCP replica (ns3_runner.cc) and the TapBridge medium (ns3_tap_bridge.cc).
// C++17 with ns-3's headers, like the rest of the ns-3 half.
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_

#include "ns3/network-module.h"

struct Ns3TwoStations {
  ns3::NodeContainer nodes;
  ns3::NetDeviceContainer devices;
};

// Nodes at (0, 0, 1) and (distance_m, 0, 1); ConstantRateWifiManager at
// `rate_mbps` (RTS at 6); Yans channel, log-distance exponent 3 with
// mac_phy_sim's 1 m loss for 802.11a, constant-speed delay; NIST error model;
// ad hoc non-QoS MAC.
Ns3TwoStations MakeTwo80211aStations(double distance_m, double rate_mbps);

// The same two nodes and channel as 802.11n stations at 5 GHz, 20 MHz, 800 ns guard interval,
// ConstantRateWifiManager at HtMcs`mcs` (RTS at 6 Mb/s): ns-3 3.37's QoS ad hoc MAC, with
// its A-MPDU defaults when `ampdu` (BE and VI 65535 B), else BE_MaxAmpduSize 0 (no A-MPDU),
// as bench/ns3_reference's saturation matrix sets its HT cells.
Ns3TwoStations MakeTwoHtStations(double distance_m, int mcs, bool ampdu);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_

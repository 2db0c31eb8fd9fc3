// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Two ad hoc 802.11a stations in ns-3 3.37 on the matrix's channel, for the
// TCP replica (ns3_runner.cc) and the TapBridge medium (ns3_tap_bridge.cc).
// C++17 with ns-3's headers, like the rest of the ns-3 half.
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_

#include <cstdint>

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

// The same two nodes and channel as QoS ad hoc stations (ns-3 3.37's AdhocWifiMac), 800 ns guard
// interval, ConstantRateWifiManager at the data mode (RTS at 6 Mb/s): 802.11n at 5 GHz, 20 MHz,
// HtMcs`mcs`; or 802.11ac (`vht`), `width_mhz` (20, 40, 80), VhtMcs`mcs`. Best effort's A-MPDU
// limit is `be_max_ampdu_bytes`: 0 turns A-MPDU off (BE_MaxAmpduSize 0), 65535 is ns-3's
// default (VI keeps its default, 65535), VHT allows up to 1048575. As bench/ns3_reference's
// saturation matrix sets its HT/VHT cells.
struct Ns3QosRadio {
  bool vht = false;
  int mcs = 7;
  int width_mhz = 20;
  uint32_t be_max_ampdu_bytes = 0;
};
Ns3TwoStations MakeTwoQosStations(double distance_m, const Ns3QosRadio& radio);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_TWO_STATIONS_H_

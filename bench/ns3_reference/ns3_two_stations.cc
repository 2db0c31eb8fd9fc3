// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
#include "ns3_two_stations.h"

#include <algorithm>
#include <string>

#include "ns3/core-module.h"
#include "ns3/mobility-module.h"
#include "ns3/propagation-module.h"
#include "ns3/wifi-module.h"
#include "ns3_runner.h"

namespace {

std::string OfdmMode(double rate_mbps) {
  return "OfdmRate" + std::to_string(static_cast<int>(rate_mbps)) + "Mbps";
}

}  // namespace

namespace {

// Two nodes `distance_m` apart on a Yans channel with the matrix's log-distance loss; `phy`
// gets the channel and the NIST error model.
Ns3TwoStations PlaceTwoNodes(double distance_m, ns3::YansWifiPhyHelper* phy) {
  using namespace ns3;
  Ns3TwoStations stations;
  stations.nodes.Create(2);
  MobilityHelper mobility;
  Ptr<ListPositionAllocator> positions = CreateObject<ListPositionAllocator>();
  positions->Add(Vector(0, 0, 1));
  positions->Add(Vector(distance_m, 0, 1));
  mobility.SetPositionAllocator(positions);
  mobility.SetMobilityModel("ns3::ConstantPositionMobilityModel");
  mobility.Install(stations.nodes);
  Ptr<YansWifiChannel> channel = CreateObject<YansWifiChannel>();
  channel->SetPropagationDelayModel(CreateObject<ConstantSpeedPropagationDelayModel>());
  Ptr<LogDistancePropagationLossModel> loss = CreateObject<LogDistancePropagationLossModel>();
  loss->SetAttribute("Exponent", DoubleValue(3));
  loss->SetAttribute("ReferenceLoss", DoubleValue(Ns3Radio{}.reference_loss_db));
  channel->SetPropagationLossModel(loss);
  phy->SetChannel(channel);
  phy->SetErrorRateModel("ns3::NistErrorRateModel");
  return stations;
}

}  // namespace

Ns3TwoStations MakeTwo80211aStations(double distance_m, double rate_mbps) {
  using namespace ns3;
  YansWifiPhyHelper phy;
  Ns3TwoStations stations = PlaceTwoNodes(distance_m, &phy);
  WifiHelper wifi;
  wifi.SetStandard(WIFI_STANDARD_80211a);
  wifi.SetRemoteStationManager("ns3::ConstantRateWifiManager", "DataMode",
                               StringValue(OfdmMode(rate_mbps)), "ControlMode",
                               StringValue(OfdmMode(6)));
  WifiMacHelper mac;
  mac.SetType("ns3::AdhocWifiMac");
  stations.devices = wifi.Install(phy, mac, stations.nodes);
  return stations;
}

Ns3TwoStations MakeTwoQosStations(double distance_m, const Ns3QosRadio& radio) {
  using namespace ns3;
  Config::SetDefault("ns3::HtConfiguration::ShortGuardIntervalSupported", BooleanValue(false));
  YansWifiPhyHelper phy;
  Ns3TwoStations stations = PlaceTwoNodes(distance_m, &phy);
  phy.Set("ChannelSettings",
          StringValue("{0, " + std::to_string(radio.width_mhz) + ", BAND_5GHZ, 0}"));
  WifiHelper wifi;
  wifi.SetStandard(radio.vht ? WIFI_STANDARD_80211ac : WIFI_STANDARD_80211n);
  // No RTS/CTS, as on sitlnet's side: ns-3 compares the whole PSDU with RtsCtsThreshold
  // (default 65535 B), so a larger A-MPDU limit needs a threshold above it (ns3_runner.cc).
  wifi.SetRemoteStationManager(
      "ns3::ConstantRateWifiManager", "DataMode",
      StringValue((radio.vht ? "VhtMcs" : "HtMcs") + std::to_string(radio.mcs)), "ControlMode",
      StringValue(OfdmMode(6)), "RtsCtsThreshold",
      UintegerValue(std::max<uint32_t>(65535, radio.be_max_ampdu_bytes)));
  WifiMacHelper mac;
  mac.SetType("ns3::AdhocWifiMac", "BE_MaxAmpduSize", UintegerValue(radio.be_max_ampdu_bytes));
  stations.devices = wifi.Install(phy, mac, stations.nodes);
  return stations;
}

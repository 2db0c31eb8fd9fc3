// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
#include "ns3_two_stations.h"

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

Ns3TwoStations MakeTwo80211aStations(double distance_m, double rate_mbps) {
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
  WifiHelper wifi;
  wifi.SetStandard(WIFI_STANDARD_80211a);
  wifi.SetRemoteStationManager("ns3::ConstantRateWifiManager", "DataMode",
                               StringValue(OfdmMode(rate_mbps)), "ControlMode",
                               StringValue(OfdmMode(6)));
  Ptr<YansWifiChannel> channel = CreateObject<YansWifiChannel>();
  channel->SetPropagationDelayModel(CreateObject<ConstantSpeedPropagationDelayModel>());
  Ptr<LogDistancePropagationLossModel> loss = CreateObject<LogDistancePropagationLossModel>();
  loss->SetAttribute("Exponent", DoubleValue(3));
  loss->SetAttribute("ReferenceLoss", DoubleValue(Ns3Radio{}.reference_loss_db));
  channel->SetPropagationLossModel(loss);
  YansWifiPhyHelper phy;
  phy.SetChannel(channel);
  phy.SetErrorRateModel("ns3::NistErrorRateModel");
  WifiMacHelper mac;
  mac.SetType("ns3::AdhocWifiMac");
  stations.devices = wifi.Install(phy, mac, stations.nodes);
  return stations;
}

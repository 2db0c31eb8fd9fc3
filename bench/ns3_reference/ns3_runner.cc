// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
//
// The ns-3 half of the side-by-side benchmark. Compiled as C++17: ns-3 3.37's
// headers do not compile as C++20 (template-id constructors).
#include "ns3_runner.h"

#include <chrono>
#include <limits>
#include <string>

#include "ns3/core-module.h"
#include "ns3/mobility-module.h"
#include "ns3/network-module.h"
#include "ns3/wifi-module.h"

namespace {

uint64_t g_rx_bytes = 0;
double g_measure_from_s = 0, g_measure_to_s = 0;

void OnRx(ns3::Ptr<const ns3::Packet> packet, const ns3::Address&) {
  const double now = ns3::Simulator::Now().GetSeconds();
  if (now > g_measure_from_s && now <= g_measure_to_s) g_rx_bytes += packet->GetSize();
}

}  // namespace

Ns3Outcome RunNs3Saturation(int n, double rate_mbps, double warmup_s, double measure_s,
                            uint32_t run) {
  using namespace ns3;
  RngSeedManager::SetSeed(1);
  RngSeedManager::SetRun(run);
  Config::SetDefault("ns3::WifiRemoteStationManager::MaxSsrc",
                     UintegerValue(std::numeric_limits<uint32_t>::max()));
  Config::SetDefault("ns3::WifiRemoteStationManager::MaxSlrc",
                     UintegerValue(std::numeric_limits<uint32_t>::max()));
  NodeContainer nodes;
  nodes.Create(n);
  WifiHelper wifi;
  wifi.SetStandard(WIFI_STANDARD_80211a);
  const std::string mode = "OfdmRate" + std::to_string(static_cast<int>(rate_mbps)) + "Mbps";
  wifi.SetRemoteStationManager("ns3::ConstantRateWifiManager", "DataMode", StringValue(mode),
                               "ControlMode", StringValue(mode));
  YansWifiChannelHelper channel = YansWifiChannelHelper::Default();
  YansWifiPhyHelper phy;
  phy.SetChannel(channel.Create());
  phy.SetErrorRateModel("ns3::NistErrorRateModel");
  WifiMacHelper mac;
  mac.SetType("ns3::AdhocWifiMac");
  NetDeviceContainer devices = wifi.Install(phy, mac, nodes);

  MobilityHelper mobility;
  Ptr<ListPositionAllocator> positions = CreateObject<ListPositionAllocator>();
  for (int i = 0; i < n; ++i) positions->Add(Vector(0.001 * i, 0, 0));
  mobility.SetPositionAllocator(positions);
  mobility.SetMobilityModel("ns3::ConstantPositionMobilityModel");
  mobility.Install(nodes);

  PacketSocketHelper packet_socket;
  packet_socket.Install(nodes);
  // Offer a packet every 100 us (or 1 ms at low rates): more than the medium carries.
  const Time interval = MicroSeconds(rate_mbps >= 24 ? 100 : 1000);
  for (int i = 0; i < n; ++i) {
    const int to = (i + 1) % n;
    PacketSocketAddress remote;
    remote.SetSingleDevice(devices.Get(i)->GetIfIndex());
    remote.SetPhysicalAddress(devices.Get(to)->GetAddress());
    remote.SetProtocol(1);
    Ptr<PacketSocketClient> client = CreateObject<PacketSocketClient>();
    client->SetRemote(remote);
    client->SetAttribute("PacketSize", UintegerValue(1500));
    client->SetAttribute("MaxPackets", UintegerValue(0));
    client->SetAttribute("Interval", TimeValue(interval));
    client->SetStartTime(Seconds(0.001 * i));
    nodes.Get(i)->AddApplication(client);

    PacketSocketAddress local;
    local.SetSingleDevice(devices.Get(to)->GetIfIndex());
    local.SetProtocol(1);
    Ptr<PacketSocketServer> server = CreateObject<PacketSocketServer>();
    server->SetLocal(local);
    server->TraceConnectWithoutContext("Rx", MakeCallback(&OnRx));
    nodes.Get(to)->AddApplication(server);
  }
  g_rx_bytes = 0;
  g_measure_from_s = warmup_s;
  g_measure_to_s = warmup_s + measure_s;
  Simulator::Stop(Seconds(warmup_s + measure_s));
  const auto start = std::chrono::steady_clock::now();
  Simulator::Run();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Simulator::Destroy();
  return {g_rx_bytes * 8.0 / measure_s / 1e6, wall};
}

// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
//
// The ns-3 half of the side-by-side benchmark. Compiled as C++17: ns-3 3.37's
// headers do not compile as C++20 (template-id constructors).
#include "ns3_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <string>

#include "ns3/buildings-module.h"
#include "ns3/core-module.h"
#include "ns3/mobility-module.h"
#include "ns3/network-module.h"
#include "ns3/propagation-module.h"
#include "ns3/wifi-module.h"
#include "ns3_two_stations.h"

namespace {

using sitlnet::side_by_side::Case;
using sitlnet::side_by_side::Standard;

uint64_t g_rx_bytes = 0;
double g_measure_from_s = 0, g_measure_to_s = 0;

void OnRx(ns3::Ptr<const ns3::Packet> packet, const ns3::Address&) {
  const double now = ns3::Simulator::Now().GetSeconds();
  if (now > g_measure_from_s && now <= g_measure_to_s) g_rx_bytes += packet->GetSize();
}

// A PHY trace for comparing first frames with mac_phy_sim's (SITLNET_NS3_PHY_TRACE="from_s,to_s"
// prints every PSDU that starts in that window to stderr: time, node, PPDU duration, MPDU count,
// the first MPDU's type, sequence number and Retry bit).
double g_trace_from_s = -1, g_trace_to_s = -1;
void OnPsduBegin(std::string context, ns3::WifiConstPsduMap psdus, ns3::WifiTxVector tx, double) {
  const double now = ns3::Simulator::Now().GetSeconds();
  if (now < g_trace_from_s || now > g_trace_to_s) return;
  for (const auto& [id, psdu] : psdus) {
    const ns3::WifiMacHeader& h = psdu->GetHeader(0);
    const ns3::Time d = ns3::WifiPhy::CalculateTxDuration(psdu->GetSize(), tx, ns3::WIFI_PHY_BAND_5GHZ);
    std::fprintf(stderr, "ns3 %.3f us node %s dur %lld us mpdus %zu %s seq %u retry %d\n",
                 now * 1e6, context.substr(10, context.find('/', 10) - 10).c_str(),
                 static_cast<long long>(d.GetMicroSeconds()), psdu->GetNMpdus(),
                 h.GetTypeString(), h.IsQosData() || h.IsMgt() ? h.GetSequenceNumber() : 0,
                 h.IsRetry() ? 1 : 0);
  }
}

double ProcessCpuS() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}

bool IsDsss(double rate_mbps) {
  return rate_mbps == 1 || rate_mbps == 2 || rate_mbps == 5.5 || rate_mbps == 11;
}

// ns-3's WifiMode names: DsssRate5_5Mbps, OfdmRate6Mbps, ErpOfdmRate54Mbps, ...
std::string ModeName(Standard standard, double rate_mbps) {
  if (IsDsss(rate_mbps)) {
    return rate_mbps == 5.5 ? "DsssRate5_5Mbps"
                            : "DsssRate" + std::to_string(static_cast<int>(rate_mbps)) + "Mbps";
  }
  const bool erp = standard == Standard::kG || standard == Standard::kN24;
  const std::string prefix = erp ? "ErpOfdmRate" : "OfdmRate";
  return prefix + std::to_string(static_cast<int>(rate_mbps)) + "Mbps";
}

ns3::WifiStandard Ns3Standard(Standard standard) {
  switch (standard) {
    case Standard::kA:
      return ns3::WIFI_STANDARD_80211a;
    case Standard::kB:
      return ns3::WIFI_STANDARD_80211b;
    case Standard::kG:
      return ns3::WIFI_STANDARD_80211g;
    case Standard::kN24:
    case Standard::kN5:
      return ns3::WIFI_STANDARD_80211n;
    case Standard::kAc:
      return ns3::WIFI_STANDARD_80211ac;
  }
  return ns3::WIFI_STANDARD_80211a;
}

// ns-3's data mode of a cell: HtMcs<i>, VhtMcs<i>, or a legacy rate.
std::string DataModeName(const Case& c) {
  if (c.standard == Standard::kAc) return "VhtMcs" + std::to_string(c.mcs);
  if (sitlnet::side_by_side::IsHtOrVht(c.standard)) return "HtMcs" + std::to_string(c.mcs);
  return ModeName(c.standard, c.rate_mbps);
}

}  // namespace

Ns3Outcome RunNs3Case(const Case& c, const Ns3Radio& radio, uint32_t run) {
  using namespace ns3;
  RngSeedManager::SetSeed(1);
  RngSeedManager::SetRun(run);
  const uint32_t retries = c.unlimited_retries ? std::numeric_limits<uint32_t>::max() : 0;
  if (retries != 0) {
    Config::SetDefault("ns3::WifiRemoteStationManager::MaxSsrc", UintegerValue(retries));
    Config::SetDefault("ns3::WifiRemoteStationManager::MaxSlrc", UintegerValue(retries));
  } else {
    Config::SetDefault("ns3::WifiRemoteStationManager::MaxSsrc", UintegerValue(7));
    Config::SetDefault("ns3::WifiRemoteStationManager::MaxSlrc", UintegerValue(4));
  }
  const bool ht = sitlnet::side_by_side::IsHtOrVht(c.standard);
  // n/ac: the cell's guard interval (a default: set for every cell, as defaults persist).
  Config::SetDefault("ns3::HtConfiguration::ShortGuardIntervalSupported", BooleanValue(c.short_gi));
  WifiHelper wifi;
  wifi.SetStandard(Ns3Standard(c.standard));
  // No RTS: ns-3's default threshold, 65535 B, which no MPDU and no A-MPDU within HT's limit
  // exceeds. ns-3 compares the whole PSDU (WifiDefaultProtectionManager), as mac_phy_sim does,
  // so an A-MPDU above the default would go with RTS/CTS; mac_phy_sim's default (0) is never:
  // with a larger limit the threshold is raised above it.
  const uint32_t no_rts_bytes = std::max<uint32_t>(65535, radio.be_max_ampdu_bytes);
  const UintegerValue rts_threshold(c.rts_threshold_bytes == 0 ? no_rts_bytes
                                                                : c.rts_threshold_bytes);
  if (c.rate_control == sitlnet::side_by_side::RateControl::kIdeal) {
    wifi.SetRemoteStationManager("ns3::IdealWifiManager", "RtsCtsThreshold", rts_threshold);
  } else if (c.rate_control == sitlnet::side_by_side::RateControl::kMinstrel) {
    // Its attributes at their defaults (UpdateStatistics 100 ms, LookAroundRate 10, EWMA 75,
    // SampleColumn 10, PacketLength 1200), as mac_phy_sim's. n/ac: Minstrel-HT, also at its
    // defaults (UpdateStatistics 50 ms, EWMA 75, SampleColumn 10, PacketLength 1200).
    wifi.SetRemoteStationManager(ht ? "ns3::MinstrelHtWifiManager" : "ns3::MinstrelWifiManager",
                                 "RtsCtsThreshold", rts_threshold);
  } else {
    wifi.SetRemoteStationManager("ns3::ConstantRateWifiManager", "DataMode",
                                 StringValue(DataModeName(c)), "ControlMode",
                                 StringValue(ModeName(c.standard, radio.rts_rate_mbps)),
                                 "RtsCtsThreshold", rts_threshold);
  }
  const sitlnet::side_by_side::Layout layout = sitlnet::side_by_side::MakeLayout(c);
  const int n = static_cast<int>(layout.positions.size());
  NodeContainer nodes;
  nodes.Create(n);
  MobilityHelper mobility;
  Ptr<ListPositionAllocator> positions = CreateObject<ListPositionAllocator>();
  for (const auto& p : layout.positions) positions->Add(Vector(p.x, p.y, p.z));
  mobility.SetPositionAllocator(positions);
  mobility.SetMobilityModel("ns3::ConstantPositionMobilityModel");
  mobility.Install(nodes);
  // The 3GPP V2V condition models ask each node's MobilityBuildingInfo (none: no buildings).
  if (sitlnet::side_by_side::IsV2v(c.path_loss)) {
    BuildingsHelper::Install(nodes);
  }

  Ptr<YansWifiChannel> channel = CreateObject<YansWifiChannel>();
  channel->SetPropagationDelayModel(CreateObject<ConstantSpeedPropagationDelayModel>());
  if (!radio.link_losses_db.empty()) {
    Ptr<MatrixPropagationLossModel> matrix = CreateObject<MatrixPropagationLossModel>();
    matrix->SetDefaultLoss(1000);
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) {
        matrix->SetLoss(nodes.Get(a)->GetObject<MobilityModel>(),
                        nodes.Get(b)->GetObject<MobilityModel>(),
                        radio.link_losses_db[static_cast<size_t>(a) * n + b]);
      }
    }
    channel->SetPropagationLossModel(matrix);
  } else if (c.path_loss == sitlnet::side_by_side::PathLoss::kTwoRayGround) {
    // Antenna heights from the stations' z (HeightAboveZ 0); SystemLoss 1, MinDistance 0.5 m.
    Ptr<TwoRayGroundPropagationLossModel> two_ray =
        CreateObject<TwoRayGroundPropagationLossModel>();
    two_ray->SetAttribute("Frequency", DoubleValue(radio.path_loss_frequency_hz));
    channel->SetPropagationLossModel(two_ray);
  } else if (sitlnet::side_by_side::IsV2v(c.path_loss)) {
    // ns-3's defaults otherwise: condition frozen per pair (UpdatePeriod 0) unless the cell
    // sets an update period.
    const bool urban = sitlnet::side_by_side::IsV2vUrban(c.path_loss);
    Ptr<ThreeGppPropagationLossModel> v2v;
    Ptr<ChannelConditionModel> condition;
    if (urban) {
      v2v = CreateObject<ThreeGppV2vUrbanPropagationLossModel>();
      condition = CreateObject<ThreeGppV2vUrbanChannelConditionModel>();
    } else {
      v2v = CreateObject<ThreeGppV2vHighwayPropagationLossModel>();
      condition = CreateObject<ThreeGppV2vHighwayChannelConditionModel>();
    }
    condition->SetAttribute("UpdatePeriod", TimeValue(MilliSeconds(c.v2v_update_period_ms)));
    v2v->SetAttribute("Frequency", DoubleValue(radio.path_loss_frequency_hz));
    v2v->SetAttribute("ShadowingEnabled",
                      BooleanValue(sitlnet::side_by_side::HasV2vShadowing(c.path_loss)));
    v2v->SetChannelConditionModel(condition);
    channel->SetPropagationLossModel(v2v);
  } else {
    Ptr<LogDistancePropagationLossModel> log_distance =
        CreateObject<LogDistancePropagationLossModel>();
    log_distance->SetAttribute("Exponent", DoubleValue(3));
    log_distance->SetAttribute("ReferenceLoss", DoubleValue(radio.reference_loss_db));
    if (c.nakagami_m > 0) {
      Ptr<NakagamiPropagationLossModel> nakagami = CreateObject<NakagamiPropagationLossModel>();
      nakagami->SetAttribute("m0", DoubleValue(c.nakagami_m));
      nakagami->SetAttribute("m1", DoubleValue(c.nakagami_m));
      nakagami->SetAttribute("m2", DoubleValue(c.nakagami_m));
      log_distance->SetNext(nakagami);
    }
    if (c.jakes) log_distance->SetNext(CreateObject<JakesPropagationLossModel>());
    channel->SetPropagationLossModel(log_distance);
  }
  YansWifiPhyHelper phy;
  phy.SetChannel(channel);
  phy.SetErrorRateModel(c.table_error_model ? "ns3::TableBasedErrorRateModel"
                                            : "ns3::NistErrorRateModel");
  if (c.capture) phy.SetFrameCaptureModel("ns3::SimpleFrameCaptureModel");
  if (ht) {
    // The default channel of the band at the cell's width (ns-3 picks the number).
    const std::string band = c.standard == Standard::kN24 ? "BAND_2_4GHZ" : "BAND_5GHZ";
    phy.Set("ChannelSettings", StringValue("{0, " + std::to_string(c.channel_width_mhz) + ", " +
                                           band + ", 0}"));
  }
  WifiMacHelper mac;
  if (sitlnet::side_by_side::IsEdcaCell(c)) {
    // QoS stations, no A-MPDU in any access category (VI's default is 65535 B).
    mac.SetType("ns3::AdhocWifiMac", "QosSupported", BooleanValue(true), "BE_MaxAmpduSize",
                UintegerValue(0), "BK_MaxAmpduSize", UintegerValue(0), "VI_MaxAmpduSize",
                UintegerValue(0), "VO_MaxAmpduSize", UintegerValue(0));
  } else if (ht && c.ampdu && radio.be_max_ampdu_bytes > 0) {
    // VHT allows up to 1048575 B (WifiMac::GetVhtCapabilities); HT caps it at 65535.
    mac.SetType("ns3::AdhocWifiMac", "BE_MaxAmpduSize", UintegerValue(radio.be_max_ampdu_bytes));
  } else if (ht && c.ampdu) {
    mac.SetType("ns3::AdhocWifiMac");  // ns-3 3.37's A-MPDU defaults (BE and VI 65535 B).
  } else if (ht) {
    mac.SetType("ns3::AdhocWifiMac", "BE_MaxAmpduSize", UintegerValue(0));  // No A-MPDU.
  } else {
    mac.SetType("ns3::AdhocWifiMac");
  }
  NetDeviceContainer devices = wifi.Install(phy, mac, nodes);
  if (const char* trace = std::getenv("SITLNET_NS3_PHY_TRACE")) {
    std::sscanf(trace, "%lf,%lf", &g_trace_from_s, &g_trace_to_s);
    Config::Connect("/NodeList/*/DeviceList/*/$ns3::WifiNetDevice/Phy/PhyTxPsduBegin",
                    MakeCallback(&OnPsduBegin));
  }
  if (c.short_slot) {
    for (uint32_t i = 0; i < devices.GetN(); ++i) {
      DynamicCast<WifiNetDevice>(devices.Get(i))->GetPhy()->SetSlot(MicroSeconds(9));
    }
  }

  PacketSocketHelper packet_socket;
  packet_socket.Install(nodes);
  const Time interval = NanoSeconds(sitlnet::side_by_side::OfferIntervalNs(c));
  // One server per receiver and priority (packet-socket protocol 1 + priority), so an EDCA cell
  // counts only its measured priority's packets.
  std::vector<std::vector<bool>> has_server(n, std::vector<bool>(8, false));
  int k = 0;
  for (const auto& flow : layout.flows) {
    PacketSocketAddress remote;
    remote.SetSingleDevice(devices.Get(flow.from)->GetIfIndex());
    remote.SetPhysicalAddress(devices.Get(flow.to)->GetAddress());
    remote.SetProtocol(1 + flow.priority);
    Ptr<PacketSocketClient> client = CreateObject<PacketSocketClient>();
    client->SetRemote(remote);
    client->SetAttribute("PacketSize", UintegerValue(c.payload_bytes));
    client->SetAttribute("MaxPackets", UintegerValue(0));
    client->SetAttribute("Interval", TimeValue(interval));
    // The socket priority becomes the TID (QosUtilsGetTidForPacket), as the DS byte does here.
    client->SetAttribute("Priority", UintegerValue(flow.priority));
    client->SetStartTime(NanoSeconds(sitlnet::side_by_side::OfferStartNs(k++)));
    nodes.Get(flow.from)->AddApplication(client);
    if (has_server[flow.to][flow.priority]) continue;
    has_server[flow.to][flow.priority] = true;
    PacketSocketAddress local;
    local.SetSingleDevice(devices.Get(flow.to)->GetIfIndex());
    local.SetProtocol(1 + flow.priority);
    Ptr<PacketSocketServer> server = CreateObject<PacketSocketServer>();
    server->SetLocal(local);
    if (!sitlnet::side_by_side::IsEdcaCell(c) || flow.priority == c.measured_priority) {
      server->TraceConnectWithoutContext("Rx", MakeCallback(&OnRx));
    }
    nodes.Get(flow.to)->AddApplication(server);
  }
  g_rx_bytes = 0;
  g_measure_from_s = c.warmup_s;
  g_measure_to_s = c.warmup_s + c.measure_s;
  Simulator::Stop(Seconds(c.warmup_s + c.measure_s));
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuS();
  Simulator::Run();
  const double cpu = ProcessCpuS() - cpu_start;
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Simulator::Destroy();
  return {g_rx_bytes * 8.0 / c.measure_s / 1e6, wall, cpu};
}

namespace {

struct TcpReplicaState {
  ns3::Ptr<ns3::Socket> b_socket;
  double turnaround_us = 0;
  uint64_t received = 0, measured = 0, ack_timeouts = 0;
};
TcpReplicaState g_replica;

void ReplicaSendAck() { g_replica.b_socket->Send(ns3::Create<ns3::Packet>(kTcpReplicaAckBytes)); }

void ReplicaOnRx(ns3::Ptr<const ns3::Packet> packet, const ns3::Address&) {
  if (packet->GetSize() != kTcpReplicaDataBytes) return;
  if (ns3::Simulator::Now() > ns3::Seconds(kTcpReplicaWarmupS)) ++g_replica.measured;
  if (++g_replica.received % 2 == 0) {
    ns3::Simulator::Schedule(ns3::NanoSeconds(static_cast<int64_t>(g_replica.turnaround_us * 1000)),
                             &ReplicaSendAck);
  }
}

void ReplicaOnResponseTimeout(uint8_t, ns3::Ptr<const ns3::WifiMpdu>, const ns3::WifiTxVector&) {
  ++g_replica.ack_timeouts;
}

}  // namespace

TcpReplicaOutcome RunNs3TcpReplica(double turnaround_us, uint32_t run) {
  using namespace ns3;
  RngSeedManager::SetSeed(1);
  RngSeedManager::SetRun(run);
  Config::SetDefault("ns3::WifiRemoteStationManager::MaxSsrc", UintegerValue(7));
  Config::SetDefault("ns3::WifiRemoteStationManager::MaxSlrc", UintegerValue(4));
  g_replica = TcpReplicaState{};
  g_replica.turnaround_us = turnaround_us;
  const Ns3TwoStations stations = MakeTwo80211aStations(kTcpReplicaDistanceM, 54);
  const NodeContainer& nodes = stations.nodes;
  const NetDeviceContainer& devices = stations.devices;
  PacketSocketHelper packet_socket;
  packet_socket.Install(nodes);
  PacketSocketAddress to_b;
  to_b.SetSingleDevice(devices.Get(0)->GetIfIndex());
  to_b.SetPhysicalAddress(devices.Get(1)->GetAddress());
  to_b.SetProtocol(1);
  Ptr<PacketSocketClient> client = CreateObject<PacketSocketClient>();
  client->SetRemote(to_b);
  client->SetAttribute("PacketSize", UintegerValue(kTcpReplicaDataBytes));
  client->SetAttribute("MaxPackets", UintegerValue(0));
  client->SetAttribute("Interval", TimeValue(MicroSeconds(150)));  // Twice what 54 Mb/s carries.
  nodes.Get(0)->AddApplication(client);
  PacketSocketAddress at_b;
  at_b.SetSingleDevice(devices.Get(1)->GetIfIndex());
  at_b.SetProtocol(1);
  Ptr<PacketSocketServer> server = CreateObject<PacketSocketServer>();
  server->SetLocal(at_b);
  server->TraceConnectWithoutContext("Rx", MakeCallback(&ReplicaOnRx));
  nodes.Get(1)->AddApplication(server);
  PacketSocketAddress to_a;
  to_a.SetSingleDevice(devices.Get(1)->GetIfIndex());
  to_a.SetPhysicalAddress(devices.Get(0)->GetAddress());
  to_a.SetProtocol(2);
  g_replica.b_socket = Socket::CreateSocket(nodes.Get(1), PacketSocketFactory::GetTypeId());
  g_replica.b_socket->Bind();
  g_replica.b_socket->Connect(to_a);
  Config::ConnectWithoutContext(
      "/NodeList/*/DeviceList/*/$ns3::WifiNetDevice/Mac/MpduResponseTimeout",
      MakeCallback(&ReplicaOnResponseTimeout));
  Simulator::Stop(Seconds(kTcpReplicaWarmupS + kTcpReplicaMeasureS));
  Simulator::Run();
  const TcpReplicaOutcome outcome{
      g_replica.measured * kTcpReplicaMssBytes * 8.0 / kTcpReplicaMeasureS / 1e6,
      g_replica.ack_timeouts};
  g_replica.b_socket = nullptr;
  Simulator::Destroy();
  return outcome;
}

// SPDX-License-Identifier: GPL-2.0-only (part of the ns-3 benchmark; see LICENSE in this folder)
//
// mac_phy_sim's half of the TCP replica: the same two stations and traffic as
// RunNs3TcpReplica, driven event by event. A keeps 60 frames ahead of what B
// has received (ns-3's source offers twice the medium's rate, so A's queue
// never runs empty either).
#include "tcp_replica.h"

#include <algorithm>
#include <map>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

TcpReplicaOutcome RunTcpReplica(double turnaround_us, uint64_t seed) {
  using namespace sitlnet;
  using namespace sitlnet::mac;
  MediumConfig config;
  config.standard = Standard::k80211a;
  config.rate_mbps = 54;
  config.propagation_delay = true;
  config.seed = seed;
  Medium medium(config);
  const StationId a = medium.AddStation(RobotMac(0), {0, 0, 1});
  const StationId b = medium.AddStation(RobotMac(1), {kTcpReplicaDistanceM, 0, 1});
  const std::vector<uint8_t> data =
      testing::MakeEthernetFrame(RobotMac(1), RobotMac(0), kTcpReplicaDataBytes);
  const std::vector<uint8_t> ack =
      testing::MakeEthernetFrame(RobotMac(0), RobotMac(1), kTcpReplicaAckBytes);
  const TimeNs turnaround_ns = static_cast<TimeNs>(turnaround_us * 1000);
  const TimeNs warmup_ns = static_cast<TimeNs>(kTcpReplicaWarmupS * kNsPerS);
  const TimeNs end_ns = warmup_ns + static_cast<TimeNs>(kTcpReplicaMeasureS * kNsPerS);
  std::multimap<TimeNs, int> acks_due;
  uint64_t submitted = 0, received = 0, measured = 0;
  std::vector<Delivery> deliveries;
  TimeNs now_ns = 0;
  while (now_ns < end_ns) {
    for (; submitted < received + 60; ++submitted) medium.SubmitFrame(a, data, now_ns);
    if (!acks_due.empty() && acks_due.begin()->first <= now_ns) {
      medium.SubmitFrame(b, ack, acks_due.begin()->first);
      acks_due.erase(acks_due.begin());
      continue;
    }
    TimeNs next_ns = end_ns;
    if (const auto event = medium.NextEventNs()) next_ns = std::min(next_ns, *event);
    if (!acks_due.empty()) next_ns = std::min(next_ns, acks_due.begin()->first);
    next_ns = std::max(next_ns, now_ns);
    deliveries.clear();
    medium.AdvanceTo(next_ns, &deliveries);
    now_ns = next_ns;
    for (const Delivery& d : deliveries) {
      if (d.station != b) continue;
      if (d.delivery_ns > warmup_ns) ++measured;
      if (++received % 2 == 0) acks_due.emplace(d.delivery_ns + turnaround_ns, 0);
    }
  }
  return {measured * kTcpReplicaMssBytes * 8.0 / kTcpReplicaMeasureS / 1e6,
          medium.counters(a).tx_failures + medium.counters(b).tx_failures};
}

// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Interface between the C++20 benchmark and its C++17 ns-3 half.
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_

#include <cstdint>
#include <vector>

#include "mac_phy_sim/test/side_by_side_case.h"

struct Ns3Outcome {
  double throughput_mbps = 0;
  double wall_s = 0;
  double cpu_s = 0;  // This process's CPU time over Simulator::Run(), like wall_s.
};

// What ns-3 needs from mac_phy_sim's configuration of the same cell, so both
// use the same values: the loss at 1 m and the rate RTS frames go at
// (ConstantRateWifiManager's ControlMode; ACK/CTS rates ns-3 derives itself).
struct Ns3Radio {
  double reference_loss_db = 46.6777;
  double rts_rate_mbps = 6;
  // With log-normal shadowing: mac_phy_sim's loss per station pair
  // (row-major), given to ns-3's MatrixPropagationLossModel instead of the
  // log-distance model, so both simulate the same realised links.
  std::vector<double> link_losses_db;
  // Carrier frequency of the two-ray and 3GPP models: mac_phy_sim's for the cell's standard.
  double path_loss_frequency_hz = 5.15e9;
  // n/ac cells with A-MPDU: ns-3's BE_MaxAmpduSize (mac_phy_sim's max_ampdu_bytes of best
  // effort); 0 keeps ns-3 3.37's default, 65535.
  uint32_t be_max_ampdu_bytes = 0;
};

// Runs cell `c` in ns-3 3.37 with RngRun `run`: ad hoc (non-QoS) 802.11a/b/g,
// ConstantRateWifiManager, Yans channel (log-distance exponent 3, or the cell's
// two-ray / 3GPP V2V model; constant-speed delay), NIST or table-based error
// model, packet sockets offering `payload_bytes` packets faster than the medium
// carries them. Returns the payload throughput over the measured window and the
// wall time of Simulator::Run().
Ns3Outcome RunNs3Case(const sitlnet::side_by_side::Case& c, const Ns3Radio& radio, uint32_t run);

// The TCP replica: the pattern of one TCP flow between two robots without
// TCP's timing. Two 802.11a stations 10 m apart at 54 Mb/s (as
// tcp_side_by_side.sh); A is saturated with 1500-byte packets for B; B
// answers every second packet it receives with a 52-byte one (a TCP ACK's
// IP packet) `turnaround_us` after the reception ends. Goodput counts 1448
// bytes (an MSS) per packet B receives after the first second, over 10 s.
constexpr double kTcpReplicaDistanceM = 10;
constexpr int kTcpReplicaDataBytes = 1500;
constexpr int kTcpReplicaAckBytes = 52;
constexpr int kTcpReplicaMssBytes = 1448;
constexpr double kTcpReplicaWarmupS = 1, kTcpReplicaMeasureS = 10;
struct TcpReplicaOutcome {
  double goodput_mbps = 0;
  uint64_t ack_timeouts = 0;  // DATA frames of either station left unacknowledged.
};
TcpReplicaOutcome RunNs3TcpReplica(double turnaround_us, uint32_t run);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_RUNNER_H_

// SPDX-License-Identifier: GPL-2.0-only (part of the ns-3 benchmark; see LICENSE in this folder)
// mac_phy_sim's half of the TCP replica (ns3_runner.h describes it).
#ifndef SITLNET_BENCH_NS3_REFERENCE_TCP_REPLICA_H_
#define SITLNET_BENCH_NS3_REFERENCE_TCP_REPLICA_H_

#include <cstdint>

#include "ns3_runner.h"

TcpReplicaOutcome RunTcpReplica(double turnaround_us, uint64_t seed);

#endif  // SITLNET_BENCH_NS3_REFERENCE_TCP_REPLICA_H_

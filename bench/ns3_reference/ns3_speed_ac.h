// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// ns3_side_by_side's 802.11ac modes (issue 44, Performance and item 7): VHT MCS 9, 80 MHz,
// 64-MPDU A-MPDUs, ns-3 3.37 against mac_phy_sim in one process.
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_SPEED_AC_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_SPEED_AC_H_

// Simulated seconds per wall second of both simulators on saturated cells of 1, 5 and 20
// senders, `rounds` ABBA rounds each; then mac_phy_sim's CPU per delivered MPDU with A-MPDU
// against aggregation off on the same cells. Prints Markdown tables; returns the exit status.
int PrintSpeedAc(int rounds, double measure_s);

// One sender's saturation throughput of the same cell, both sides, `seeds` seeds each: the
// figure a real iperf3 flow on that radio is held to (ac_iperf3_dilated.sh).
int PrintSaturationAc(int seeds, double measure_s);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_SPEED_AC_H_

// The benchmarks' light saturation driver for any medium configuration and cell layout: the
// medium's own cost, without a packet source in the loop. Every flow's sender keeps a fixed
// number of frames queued, topped up at a fixed period; deliveries are counted, not kept.
// (testing::RunCase offers traffic as ns-3 does and is the one to validate with; this one times.)
#ifndef SITLNET_BENCH_MAC_PHY_SIM_TOP_UP_DRIVER_H_
#define SITLNET_BENCH_MAC_PHY_SIM_TOP_UP_DRIVER_H_

#include <cstdint>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/side_by_side_case.h"

namespace sitlnet::mac::bench {

struct TopUpSetup {
  side_by_side::Layout layout;  // Stations and flows (side_by_side::MakeLayout of a cell).
  int payload_bytes = 1500;     // Ethernet payload of every frame.
  TimeNs warmup_ns = kNsPerS / 2;
  TimeNs measure_ns = 5 * kNsPerS;
  // Kept queued per sender, topped up every `top_up_ns`. 802.11ac at 390 Mb/s carries about 30
  // 1500-byte MPDUs per ms; 192 frames every 1 ms keep three 64-MPDU A-MPDUs waiting.
  int queued_frames = 192;
  TimeNs top_up_ns = kNsPerMs;
};

struct TopUpOutcome {
  uint64_t mpdus_delivered = 0;  // Data frames handed up in the measured window.
  uint64_t mpdus_delivered_all = 0;  // The same over the whole loop (what cpu_s paid for).
  double payload_mbps = 0;       // Their payload bits per second of measured virtual time.
  double mpdus_per_ampdu = 0;    // DATA transmissions per A-MPDU sent (retries included); 0: none.
  double wall_s = 0;             // The medium's loop (warm-up and measured window), set-up excluded.
  double cpu_s = 0;              // This process's CPU time over the same loop.
};

TopUpOutcome RunTopUp(const MediumConfig& config, const TopUpSetup& setup);

}  // namespace sitlnet::mac::bench

#endif  // SITLNET_BENCH_MAC_PHY_SIM_TOP_UP_DRIVER_H_

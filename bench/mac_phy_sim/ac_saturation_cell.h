// The 802.11ac saturation cell of the speed comparison with ns-3 (issue 44, Performance;
// bench/ns3_reference/ac_speed.sh) and mac_phy_sim's run of it with the light driver, shared by
// ns3_side_by_side (GPL half) and mac_phy_sim_bench (profiles without ns-3 in the process).
#ifndef SITLNET_BENCH_MAC_PHY_SIM_AC_SATURATION_CELL_H_
#define SITLNET_BENCH_MAC_PHY_SIM_AC_SATURATION_CELL_H_

#include <cstdint>

#include "bench/mac_phy_sim/top_up_driver.h"
#include "mac_phy_sim/test/side_by_side_case.h"

namespace sitlnet::mac::bench {

// Best effort's A-MPDU limit in the cell: ns-3 3.37's VHT maximum, 2^20 - 1 B
// (WifiMac::GetVhtCapabilities caps the advertised length there), also radio.ampdu_max_bytes_be's
// bound. 64 subframes of 1500-byte payloads take 98560 B, so the 64-MPDU Block Ack window, not
// the byte limit, bounds an A-MPDU.
inline constexpr uint32_t kVhtMaxAmpduBytes = 1048575;

// VHT MCS 9, 80 MHz, long GI, one spatial stream (390 Mb/s), 1500-byte payloads, `senders`
// stations 1 mm apart sending to one receive-only station, 0.5 s of warm-up, then `measure_s`;
// A-MPDU (`ampdu`, limit kVhtMaxAmpduBytes) or every MPDU alone with a normal ACK.
side_by_side::Case AcSaturationCell(int senders, double measure_s, bool ampdu);

// mac_phy_sim's run of such a cell with seed `seed` (RunTopUp, frames topped up every 1 ms).
TopUpOutcome RunAcSaturationCell(const side_by_side::Case& c, uint64_t seed);

}  // namespace sitlnet::mac::bench

#endif  // SITLNET_BENCH_MAC_PHY_SIM_AC_SATURATION_CELL_H_

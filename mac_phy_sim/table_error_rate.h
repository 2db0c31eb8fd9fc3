// The table-based error model of ns-3 3.37 (TableBasedErrorRateModel, the
// default of its Wi-Fi PHY): for OFDM, the PER of a chunk comes from tables
// of link-level simulations (per_tables.h) instead of a formula. A pure
// function; DSSS chunks never reach it (ns-3, like error_rate.cc, applies the
// DSSS formulas whatever the error model).
//
// What ns-3 does, as this file reproduces it (facts read in ns-3's
// table-based-error-rate-model.cc and yans-error-rate-model.cc at 3.37):
// - the chunk's bit count is truncated to whole bits (rate x duration), its
//   size is bits / 8 (integer division) but at least 1 byte;
// - the SNR is rounded to 0.01 dB; the table is the 32-byte one for chunks
//   under 400 bytes (attribute SizeThreshold), else the 1458-byte one;
// - PER: the table's value at that SNR, linear between points, 1 below the
//   first and 0 above the last; for a size S other than the table's T it is
//   1 - (1 - PER)^(S / T) (IEEE 802.11-14/0803r1); a PER under 1e-5 is 0;
// - a mode with no MCS (OFDM BPSK 3/4, 9 Mb/s) falls back to ns-3's Yans
//   model: BER of BPSK at Eb/N0 = SNR x 20 MHz / 12 Mb/s, then the first
//   term of the union bound of the rate-3/4 code (d_free 5, a_dfree 8).
#ifndef SITLNET_MAC_PHY_SIM_TABLE_ERROR_RATE_H_
#define SITLNET_MAC_PHY_SIM_TABLE_ERROR_RATE_H_

#include "mac_phy_sim/phy_mode.h"

namespace sitlnet::mac {

// Success probability of `bits` bits of an OFDM `mode` at linear SINR `sinr`.
double TableBasedChunkSuccessRate(const PhyMode& mode, double sinr, double bits);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_TABLE_ERROR_RATE_H_

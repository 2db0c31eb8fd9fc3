// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// ns-3 3.37's own error models called directly: the oracle for mac_phy_sim's
// (ns3_side_by_side error-rates).
#ifndef SITLNET_BENCH_NS3_REFERENCE_NS3_ERROR_RATE_H_
#define SITLNET_BENCH_NS3_REFERENCE_NS3_ERROR_RATE_H_

#include <cstdint>

// Chunk success rate of `bits` bits of the 802.11a OFDM rate `rate_mbps` at
// linear SNR `snr`, from ns-3's TableBasedErrorRateModel (table_based) or
// NistErrorRateModel, with their default attributes.
double Ns3OfdmChunkSuccessRate(bool table_based, double rate_mbps, double snr, uint64_t bits);

#endif  // SITLNET_BENCH_NS3_REFERENCE_NS3_ERROR_RATE_H_

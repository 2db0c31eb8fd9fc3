// Error-rate model: probability that a chunk of `bits` bits sent in `mode`
// at a constant SINR is received without error. A pure function.
//
// Source: the NIST model as implemented in ns-3 (NistErrorRateModel; Pei and
// Henderson, "Validation of OFDM error rate model in ns-3", 2010): uncoded
// BER of the constellation, then the union bound of the punctured K=7
// convolutional code with the distance spectra of Frenger et al. (rate 1/2)
// and Haccoun & Begin (2/3, 3/4), P_chunk = (1 - Pe)^bits. DSSS rates use
// ns-3's DsssErrorRateModel formulas (DBPSK, DQPSK, CCK by numerical
// integration of the 8-ary orthogonal symbol error probability).
// Tested against ns-3's published spot values (docs/mac_phy_sim.md).
#ifndef SITLNET_MAC_PHY_SIM_ERROR_RATE_H_
#define SITLNET_MAC_PHY_SIM_ERROR_RATE_H_

#include "mac_phy_sim/phy_mode.h"

namespace sitlnet::mac {

// Success probability of `bits` bits in `mode` at linear SINR `sinr`, NIST model.
double ChunkSuccessRate(const PhyMode& mode, double sinr, double bits);

// The same with the chosen error model: kNist as above; kTableBased the
// tables of table_error_rate.h for OFDM modes, the DSSS formulas otherwise.
double ChunkSuccessRate(MediumConfig::ErrorModel model, const PhyMode& mode, double sinr,
                        double bits);

// Smallest linear SINR above which every chunk of `mode` up to 2400 bytes
// succeeds with probability exactly 1 under `model` (computed once; lets the
// hot path skip the model).
double PerfectSinr(MediumConfig::ErrorModel model, const PhyMode& mode);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_ERROR_RATE_H_

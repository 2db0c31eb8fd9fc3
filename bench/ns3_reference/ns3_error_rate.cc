// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Compiled as C++17: ns-3 3.37's headers do not compile as C++20.
#include "ns3_error_rate.h"

#include "ns3/core-module.h"
#include "ns3/wifi-module.h"

double Ns3OfdmChunkSuccessRate(bool table_based, double rate_mbps, double snr, uint64_t bits) {
  using namespace ns3;
  static const Ptr<ErrorRateModel> table = CreateObject<TableBasedErrorRateModel>();
  static const Ptr<ErrorRateModel> nist = CreateObject<NistErrorRateModel>();
  const WifiMode mode = OfdmPhy::GetOfdmRate(static_cast<uint64_t>(rate_mbps * 1e6), 20);
  WifiTxVector tx_vector;
  tx_vector.SetMode(mode);
  tx_vector.SetChannelWidth(20);
  return (table_based ? table : nist)->GetChunkSuccessRate(mode, tx_vector, snr, bits);
}

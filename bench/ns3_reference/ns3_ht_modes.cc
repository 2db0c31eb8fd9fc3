// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
//
// Prints ns-3 3.37's own numbers for every HT and VHT mode that mac_phy_sim models, as CSV on
// stdout: the data rate and PPDU durations (WifiPhy::CalculateTxDuration), and both error models'
// chunk success rates (NistErrorRateModel, TableBasedErrorRateModel) over a range of SNRs.
// mac_phy_sim/test/data/ns3_ht_vht_modes.csv is this program's output; phy_mode_test and
// error_rate_test compare mac_phy_sim against it. Compiled as C++17 (ns-3 3.37's headers).
//
//   build/bin/ns3_ht_modes > mac_phy_sim/test/data/ns3_ht_vht_modes.csv
#include <cmath>
#include <cstdio>
#include <string>

#include "ns3/core-module.h"
#include "ns3/wifi-module.h"

namespace {

using namespace ns3;

// The PSDU sizes timed: an ACK-sized frame, a small, a 1500-byte IP packet's QoS MPDU, the most.
constexpr uint32_t kPsduBytes[] = {14, 100, 1538, 2304};
// Chunk sizes for the error models: under and over the table model's 400-byte threshold.
constexpr uint64_t kChunkBits[] = {8 * 100, 8 * 1538};

struct Standard {
  const char* name;  // As mac_phy_sim's test reads it.
  WifiPhyBand band;
  bool vht;
};

void PrintMode(const Standard& standard, uint8_t mcs, uint8_t nss, uint16_t width, uint16_t gi) {
  const WifiMode mode = standard.vht ? VhtPhy::GetVhtMcs(mcs) : HtPhy::GetHtMcs(mcs);
  WifiTxVector tx;
  tx.SetMode(mode);
  tx.SetNss(nss);
  tx.SetChannelWidth(width);
  tx.SetGuardInterval(gi);
  tx.SetPreambleType(standard.vht ? WIFI_PREAMBLE_VHT_SU : WIFI_PREAMBLE_HT_MF);
  if (standard.vht && !VhtPhy::IsCombinationAllowed(mcs, width, nss)) {
    std::printf("rate,%s,%u,%u,%u,%u,invalid\n", standard.name, mcs, nss, width, gi);
    return;
  }
  std::printf("rate,%s,%u,%u,%u,%u,%llu\n", standard.name, mcs, nss, width, gi,
              static_cast<unsigned long long>(mode.GetDataRate(tx)));
  for (uint32_t bytes : kPsduBytes) {
    std::printf("duration,%s,%u,%u,%u,%u,%u,%lld\n", standard.name, mcs, nss, width, gi, bytes,
                static_cast<long long>(
                    WifiPhy::CalculateTxDuration(bytes, tx, standard.band).GetNanoSeconds()));
  }
}

void PrintErrorRates(bool vht, uint8_t mcs) {
  static const Ptr<ErrorRateModel> table = CreateObject<TableBasedErrorRateModel>();
  static const Ptr<ErrorRateModel> nist = CreateObject<NistErrorRateModel>();
  const WifiMode mode = vht ? VhtPhy::GetVhtMcs(mcs) : HtPhy::GetHtMcs(mcs);
  WifiTxVector tx;
  tx.SetMode(mode);
  tx.SetNss(vht ? 1 : 1 + mcs / 8);
  tx.SetChannelWidth(vht ? 80 : 20);
  for (int tenth_db = -50; tenth_db <= 400; tenth_db += 5) {
    const double snr = std::pow(10.0, tenth_db / 100.0);
    for (uint64_t bits : kChunkBits) {
      std::printf("error,%s,%u,%.1f,%llu,%.17g,%.17g\n", vht ? "vht" : "ht", mcs, tenth_db / 10.0,
                  static_cast<unsigned long long>(bits),
                  nist->GetChunkSuccessRate(mode, tx, snr, bits),
                  table->GetChunkSuccessRate(mode, tx, snr, bits));
    }
  }
}

}  // namespace

int main() {
  std::printf("# ns-3 3.37 (bench/ns3_reference/ns3_ht_modes.cc)\n");
  std::printf("# rate,standard,mcs,nss,width_mhz,gi_ns,data_rate_bps\n");
  std::printf("# duration,standard,mcs,nss,width_mhz,gi_ns,psdu_bytes,ppdu_ns\n");
  std::printf("# error,format,mcs,snr_db,bits,nist_success,table_success\n");
  const Standard standards[] = {{"80211n_2_4ghz", WIFI_PHY_BAND_2_4GHZ, false},
                                {"80211n_5ghz", WIFI_PHY_BAND_5GHZ, false},
                                {"80211ac", WIFI_PHY_BAND_5GHZ, true}};
  for (const Standard& standard : standards) {
    for (uint16_t width : {20, 40, 80}) {
      if (width == 80 && !standard.vht) continue;
      for (uint16_t gi : {800, 400}) {
        for (uint8_t nss = 1; nss <= 2; ++nss) {
          for (uint8_t m = 0; m < (standard.vht ? 10 : 8); ++m) {
            PrintMode(standard, standard.vht ? m : m + 8 * (nss - 1), nss, width, gi);
          }
        }
      }
    }
  }
  for (uint8_t mcs = 0; mcs < 16; ++mcs) PrintErrorRates(false, mcs);
  for (uint8_t mcs = 0; mcs < 10; ++mcs) PrintErrorRates(true, mcs);
  return 0;
}

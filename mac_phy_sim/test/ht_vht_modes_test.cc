// HT and VHT modes against ns-3 3.37's own numbers: data rates, PPDU durations and both error
// models' chunk success rates for every MCS, stream count, width and guard interval modelled.
// The oracle, test/data/ns3_ht_vht_modes.csv, is the output of bench/ns3_reference/ns3_ht_modes
// (ns-3's WifiPhy::CalculateTxDuration, WifiMode::GetDataRate, NistErrorRateModel and
// TableBasedErrorRateModel called directly).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

std::vector<std::vector<std::string>> OracleRows(const std::string& kind) {
  const char* source = std::getenv("SITLNET_SOURCE_DIR");
  const std::string path =
      std::string(source ? source : ".") + "/mac_phy_sim/test/data/ns3_ht_vht_modes.csv";
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (fields[0] == kind) rows.push_back(fields);
  }
  return rows;
}

Standard StandardNamed(const std::string& name) {
  if (name == "80211n_2_4ghz") return Standard::k80211n2_4GHz;
  if (name == "80211n_5ghz") return Standard::k80211n5GHz;
  return Standard::k80211ac;
}

// The mode of an oracle row: standard, mcs, nss, width, gi_ns in fields 1-5.
PhyMode ModeOfRow(const std::vector<std::string>& row) {
  return McsModeFor(StandardNamed(row[1]), std::stoi(row[2]), std::stoi(row[3]),
                    std::stoi(row[4]), row[5] == "400");
}

TEST(HtVhtModesTest, DataRatesMatchNs3) {
  const auto rows = OracleRows("rate");
  // n: 2 bands x 2 widths x 2 GIs x 2 stream counts x 8 MCSs; ac: 3 widths x 2 x 2 x 10.
  ASSERT_EQ(rows.size(), 2u * 2 * 2 * 2 * 8 + 3 * 2 * 2 * 10);
  for (const auto& row : rows) {
    const std::string what = row[1] + " mcs " + row[2] + " nss " + row[3] + " " + row[4] +
                             " MHz gi " + row[5];
    if (row[6] == "invalid") {
      EXPECT_THROW(ModeOfRow(row), Error) << what;
      continue;
    }
    // ns-3 rounds each stream's rate up to whole bits per second (HtPhy::CalculateDataRate).
    const double ns3_bps = std::stod(row[6]);
    const double ours_bps = ModeOfRow(row).rate_mbps * 1e6;
    EXPECT_LE(ns3_bps - ours_bps, std::stod(row[3])) << what;
    EXPECT_GE(ns3_bps - ours_bps, 0.0) << what;
  }
}

TEST(HtVhtModesTest, PpduDurationsMatchNs3) {
  const auto rows = OracleRows("duration");
  ASSERT_EQ(rows.size(), 4u * (2 * 2 * 2 * 2 * 8 + 3 * 2 * 2 * 10 - 4));  // 4 sizes, valid modes.
  for (const auto& row : rows) {
    const Standard standard = StandardNamed(row[1]);
    const PhyMode mode = ModeOfRow(row);
    const int psdu_bytes = std::stoi(row[6]);
    EXPECT_EQ(PpduDurationNs(mode, HeaderFor(standard, mode, false), psdu_bytes),
              std::stoll(row[7]))
        << row[1] << " mcs " << row[2] << " nss " << row[3] << " " << row[4] << " MHz gi "
        << row[5] << " " << psdu_bytes << " bytes";
  }
}

TEST(HtVhtModesTest, ErrorModelsMatchNs3) {
  const auto rows = OracleRows("error");
  ASSERT_EQ(rows.size(), (16u + 10u) * 91 * 2);
  int compared_below_one = 0;
  for (const auto& row : rows) {
    const bool vht = row[1] == "vht";
    const int mcs = std::stoi(row[2]);
    const PhyMode mode = vht ? McsModeFor(Standard::k80211ac, mcs, 1, 80, false)
                             : McsModeFor(Standard::k80211n5GHz, mcs, mcs / 8 + 1, 20, false);
    const double snr = std::pow(10.0, std::stod(row[3]) / 10);
    const double bits = std::stod(row[4]);
    const double nist = std::stod(row[5]), table = std::stod(row[6]);
    const std::string what = row[1] + " mcs " + row[2] + " at " + row[3] + " dB, " + row[4] + " bits";
    EXPECT_NEAR(ChunkSuccessRate(MediumConfig::ErrorModel::kNist, mode, snr, bits), nist,
                1e-9 + 1e-9 * nist)
        << "NIST " << what;
    EXPECT_NEAR(ChunkSuccessRate(MediumConfig::ErrorModel::kTableBased, mode, snr, bits), table,
                1e-9 + 1e-9 * table)
        << "table " << what;
    if (nist > 1e-6 && nist < 1 - 1e-6) ++compared_below_one;
  }
  // The sweep crosses every MCS's waterfall, not only its flat ends.
  EXPECT_GE(compared_below_one, 26 * 2);
}

TEST(HtVhtModesTest, PreamblesAsNs3TimesThem) {
  // HT-mixed: 16 + 4 (L-SIG) + 8 (HT-SIG) + 4 (HT-STF) + 4 per HT-LTF; VHT SU the same with
  // VHT-SIG-A, no VHT-SIG-B (ns-3 3.37 sends it only in MU PPDUs).
  EXPECT_EQ(HeaderFor(Standard::k80211n5GHz, McsModeFor(Standard::k80211n5GHz, 7, 1, 20, false),
                      false).preamble_and_header_ns, 36 * kNsPerUs);
  EXPECT_EQ(HeaderFor(Standard::k80211ac, McsModeFor(Standard::k80211ac, 9, 2, 80, true), false)
                .preamble_and_header_ns, 40 * kNsPerUs);
  EXPECT_EQ(HeaderFor(Standard::k80211n2_4GHz, McsModeFor(Standard::k80211n2_4GHz, 0, 1, 20, false),
                      false).signal_extension_ns, 6 * kNsPerUs);
}

TEST(HtVhtModesTest, RefusesWhatNs3Refuses) {
  EXPECT_THROW(McsModeFor(Standard::k80211n5GHz, 16, 2, 20, false), Error);
  EXPECT_THROW(McsModeFor(Standard::k80211n5GHz, 7, 2, 20, false), Error);  // HT MCS 7: 1 stream.
  EXPECT_THROW(McsModeFor(Standard::k80211n5GHz, 7, 1, 80, false), Error);  // n has no 80 MHz.
  EXPECT_THROW(McsModeFor(Standard::k80211ac, 10, 1, 80, false), Error);
  EXPECT_THROW(McsModeFor(Standard::k80211ac, 0, 3, 80, false), Error);
  EXPECT_THROW(McsModeFor(Standard::k80211a, 0, 1, 20, false), Error);
}

TEST(HtVhtModesTest, NoiseFloorGrowsWithWidth) {
  // kTB at 290 K: -100.97 dBm over 20 MHz (k = 1.3803e-23, as ns-3), +3.01 dB per doubling.
  EXPECT_NEAR(NoiseFloorDbm(20e6, 0), -100.97, 0.01);
  EXPECT_NEAR(NoiseFloorDbm(40e6, 0) - NoiseFloorDbm(20e6, 0), 10 * std::log10(2.0), 1e-12);
  MediumConfig ac;
  ac.standard = Standard::k80211ac;
  ac.mcs = 9;
  EXPECT_NEAR(DerivePhyInfo(ac).noise_floor_dbm, NoiseFloorDbm(80e6, 7), 1e-12);  // 80 MHz default.
}

TEST(HtVhtModesTest, ControlResponsesAtTheBasicRateBelowTheMcs) {
  // ns-3's GetControlAnswerMode (modulation, then code rate): BPSK 6, QPSK 12, 16-QAM and up 24.
  const double expected[10] = {6, 12, 12, 24, 24, 24, 24, 24, 24, 24};
  for (int mcs = 0; mcs < 10; ++mcs) {
    EXPECT_EQ(ControlRateFor(Standard::k80211ac, McsModeFor(Standard::k80211ac, mcs, 1, 80, false)),
              expected[mcs]) << mcs;
  }
}

TEST(HtVhtModesTest, QosStationsUseBestEffortAifs) {
  MediumConfig n;
  n.standard = Standard::k80211n5GHz;
  const PhyInfo info = DerivePhyInfo(n);
  EXPECT_TRUE(info.qos);
  EXPECT_EQ(info.aifs_ns, (16 + 3 * 9) * kNsPerUs);  // SIFS + AIFSN 3 slots.
  EXPECT_EQ(info.eifs_ns, (16 + 44 + 43) * kNsPerUs);  // SIFS + 6 Mb/s ACK + AIFS.
  EXPECT_EQ(info.cw_min, 15);
  EXPECT_EQ(info.cw_max, 1023);
  MediumConfig a;
  EXPECT_FALSE(DerivePhyInfo(a).qos);
  EXPECT_EQ(DerivePhyInfo(a).aifs_ns, DerivePhyInfo(a).difs_ns);
  EXPECT_EQ(MpduBytesForEthernet(1514, true), 1514 - 14 + 26 + 8 + 4);
}

// ns-3's duration of a PSDU of `psdu_bytes` (one of the oracle's sizes) for a mode row.
TimeNs Ns3DurationNs(const std::string& standard, int mcs, int width, int psdu_bytes) {
  for (const auto& row : OracleRows("duration")) {
    if (row[1] == standard && std::stoi(row[2]) == mcs && row[3] == "1" &&
        std::stoi(row[4]) == width && row[5] == "800" && std::stoi(row[6]) == psdu_bytes) {
      return std::stoll(row[7]);
    }
  }
  ADD_FAILURE() << "no oracle row";
  return 0;
}

// One unicast frame between two n/ac stations: a QoS Data frame at the MCS, its PSDU as ns-3
// builds it (VHT: an S-MPDU, 4 bytes more), and an ACK at the legacy basic rate SIFS later.
TEST(HtVhtModesTest, OneFrameAsNs3SendsIt) {
  for (const bool vht : {false, true}) {
    MediumConfig config;
    config.standard = vht ? Standard::k80211ac : Standard::k80211n5GHz;
    config.mcs = vht ? 9 : 7;
    // No A-MPDU. A VHT station still sets up a Block Ack agreement, as ns-3 does: its ADDBA
    // Request and Response, each with its ACK, come first (vht_agreement_test.cc).
    config.aggregation = false;
    Medium medium(config);
    medium.EnableTrace(true);
    const MacAddress a{{2, 0, 0, 0, 0, 1}}, b{{2, 0, 0, 0, 0, 2}};
    medium.AddStation(a, {0, 0, 0});
    medium.AddStation(b, {1, 0, 0});
    // An MPDU (QoS header 26 + LLC/SNAP 8 + FCS 4) whose PSDU is 1538 bytes, an oracle size.
    const int payload_bytes = 1538 - 26 - 8 - 4 - (vht ? 4 : 0);
    medium.SubmitFrame(0, testing::MakeEthernetFrame(b, a, payload_bytes), 0);
    std::vector<Delivery> deliveries;
    medium.AdvanceTo(10 * kNsPerMs, &deliveries);
    ASSERT_EQ(deliveries.size(), 1u);
    std::vector<TxRecord> txs = testing::DrainTransmissions(medium);
    ASSERT_EQ(txs.size(), vht ? 6u : 2u);
    if (vht) txs.erase(txs.begin(), txs.begin() + 4);
    const TxRecord& data = txs[0];
    EXPECT_EQ(data.kind, FrameKind::kData);
    EXPECT_TRUE(data.qos);
    EXPECT_EQ(data.mcs, config.mcs);
    EXPECT_EQ(data.vht, vht);
    EXPECT_EQ(data.channel_width_mhz, vht ? 80 : 20);
    EXPECT_EQ(data.end_ns - data.start_ns,
              Ns3DurationNs(vht ? "80211ac" : "80211n_5ghz", config.mcs, vht ? 80 : 20, 1538));
    EXPECT_EQ(MpduBytes(data)[0], 0x88);  // QoS Data.
    const TxRecord& ack = txs[1];
    EXPECT_EQ(ack.kind, FrameKind::kAck);
    EXPECT_EQ(ack.rate_mbps, 24);
    EXPECT_EQ(ack.mcs, -1);
    EXPECT_EQ(ack.start_ns, data.end_ns + 16 * kNsPerUs);
    EXPECT_EQ(ack.end_ns - ack.start_ns, PpduDurationNs(Standard::k80211a, 24, kAckBytes));
  }
}

}  // namespace
}  // namespace sitlnet::mac

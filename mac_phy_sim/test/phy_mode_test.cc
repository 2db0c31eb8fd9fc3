// Airtime, interframe spaces and control rates against IEEE 802.11-2016 and
// the oracle table of docs/references.md#80211-timing.
#include "mac_phy_sim/phy_mode.h"

#include <gtest/gtest.h>

#include <string>

namespace sitlnet::mac {
namespace {

TEST(PhyModeTest, OfdmAirtimeMatchesReferenceTable) {
  // docs/references.md#80211-timing, the OFDM TXTIME formula at L = 14, 92, 612, 1536.
  const double rates[] = {6, 9, 12, 18, 24, 36, 48, 54};
  const struct {
    int psdu_bytes;
    int airtime_us[8];
  } rows[] = {
      {14, {44, 36, 32, 28, 28, 24, 24, 24}},
      {92, {148, 108, 84, 64, 52, 44, 36, 36}},
      {612, {840, 568, 432, 296, 228, 160, 124, 112}},
      {1536, {2072, 1388, 1048, 704, 536, 364, 280, 248}},
  };
  for (const auto& row : rows) {
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(PpduDurationNs(Standard::k80211a, rates[i], row.psdu_bytes),
                row.airtime_us[i] * kNsPerUs)
          << "L=" << row.psdu_bytes << " rate=" << rates[i];
    }
  }
}

TEST(PhyModeTest, ErpOfdmAddsSignalExtension) {
  // 18.3.2.4: ERP-OFDM PPDUs end with 6 us of signal extension.
  EXPECT_EQ(PpduDurationNs(Standard::k80211g, 54, 1536), (248 + 6) * kNsPerUs);
}

TEST(PhyModeTest, DsssAirtimeLongPreamble) {
  // 192 + ceil(8 L / R) us.
  EXPECT_EQ(PpduDurationNs(Standard::k80211b, 1, 14), (192 + 112) * kNsPerUs);
  EXPECT_EQ(PpduDurationNs(Standard::k80211b, 11, 1536), (192 + 1118) * kNsPerUs);   // 1117.1
  EXPECT_EQ(PpduDurationNs(Standard::k80211b, 5.5, 1536), (192 + 2235) * kNsPerUs);  // 2234.2
  EXPECT_EQ(PpduDurationNs(Standard::k80211b, 2, 1536), (192 + 6144) * kNsPerUs);
}

TEST(PhyModeTest, RejectsRatesTheStandardLacks) {
  EXPECT_THROW(PpduDurationNs(Standard::k80211a, 11, 100), Error);
  EXPECT_THROW(PpduDurationNs(Standard::k80211b, 54, 100), Error);
}

TEST(PhyModeTest, TimingPerStandard) {
  // docs/references.md#80211-timing.
  MediumConfig a;
  const PhyInfo pa = DerivePhyInfo(a);
  EXPECT_EQ(pa.slot_ns, 9 * kNsPerUs);
  EXPECT_EQ(pa.sifs_ns, 16 * kNsPerUs);
  EXPECT_EQ(pa.difs_ns, 34 * kNsPerUs);
  EXPECT_EQ(pa.eifs_ns, 94 * kNsPerUs);
  EXPECT_EQ(pa.cw_min, 15);
  EXPECT_EQ(pa.cw_max, 1023);
  MediumConfig b;
  b.standard = Standard::k80211b;
  b.rate_mbps = 11;
  const PhyInfo pb = DerivePhyInfo(b);
  EXPECT_EQ(pb.slot_ns, 20 * kNsPerUs);
  EXPECT_EQ(pb.sifs_ns, 10 * kNsPerUs);
  EXPECT_EQ(pb.difs_ns, 50 * kNsPerUs);
  EXPECT_EQ(pb.eifs_ns, 364 * kNsPerUs);
  EXPECT_EQ(pb.cw_min, 31);
  MediumConfig g;
  g.standard = Standard::k80211g;
  EXPECT_EQ(DerivePhyInfo(g).difs_ns, 50 * kNsPerUs);
  g.short_slot = true;
  EXPECT_EQ(DerivePhyInfo(g).difs_ns, 28 * kNsPerUs);
}

TEST(PhyModeTest, ControlRateIsHighestBasicRateNotAbove) {
  EXPECT_EQ(ControlRateFor(Standard::k80211a, 54), 24);
  EXPECT_EQ(ControlRateFor(Standard::k80211a, 18), 12);
  EXPECT_EQ(ControlRateFor(Standard::k80211a, 9), 6);
  EXPECT_EQ(ControlRateFor(Standard::k80211b, 1), 1);
  EXPECT_EQ(ControlRateFor(Standard::k80211g, 54), 24);
  EXPECT_EQ(ControlRateFor(Standard::k80211g, 9), 6);
}

TEST(PhyModeTest, EveryDsssRateIsBasicSoAnAckGoesAtTheDataRate) {
  // All four DSSS/HR-DSSS rates are mandatory (IEEE 802.11-2016 16.1.1) and
  // ns-3's ad hoc MAC makes every mandatory rate basic
  // (WifiRemoteStationManager::AddAllSupportedModes), so an 11 Mb/s frame is
  // answered at 11 Mb/s: a 203 us ACK instead of 248 us at 2 Mb/s.
  EXPECT_EQ(ControlRateFor(Standard::k80211b, 11), 11);
  EXPECT_EQ(ControlRateFor(Standard::k80211b, 5.5), 5.5);
  EXPECT_EQ(ControlRateFor(Standard::k80211b, 2), 2);
  EXPECT_EQ(ControlRateFor(Standard::k80211g, 11), 11);  // ERP PHY sending DSSS.
  MediumConfig b;
  b.standard = Standard::k80211b;
  b.rate_mbps = 11;
  EXPECT_EQ(DerivePhyInfo(b).ack_rate_mbps, 11);
  EXPECT_EQ(PpduDurationNs(Standard::k80211b, 11, kAckBytes), 203 * kNsPerUs);
}

TEST(PhyModeTest, GroupFramesDefaultToTheLowestBasicRate) {
  // ns-3 3.37 GetNonUnicastMode: the first basic mode (6 Mb/s OFDM; 1 Mb/s
  // DSSS for 11b and for 11g, whose PHY includes the DSSS rates).
  MediumConfig a;
  EXPECT_EQ(DerivePhyInfo(a).group_rate_mbps, 6);
  MediumConfig g;
  g.standard = Standard::k80211g;
  EXPECT_EQ(DerivePhyInfo(g).group_rate_mbps, 1);
  g.group_rate_mbps = 24;
  EXPECT_EQ(DerivePhyInfo(g).group_rate_mbps, 24);
  a.group_rate_mbps = 11;  // Not an 11a rate: refused, naming the field.
  try {
    DerivePhyInfo(a);
    FAIL() << "group_rate_mbps 11 accepted for 11a";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("group_rate_mbps"), std::string::npos) << e.what();
  }
}

TEST(PhyModeTest, ErpEifsUsesTheDsssAckTime) {
  // ns-3 configures 11g on top of 11b, so EIFS = SIFS + 304 us + DIFS:
  // 364 us with the long slot, 342 us with the short one.
  MediumConfig g;
  g.standard = Standard::k80211g;
  EXPECT_EQ(DerivePhyInfo(g).eifs_ns, 364 * kNsPerUs);
  g.short_slot = true;
  EXPECT_EQ(DerivePhyInfo(g).eifs_ns, 342 * kNsPerUs);
}

TEST(PhyModeTest, ShortDsssPreambleOnlyAtHrDsssRates) {
  // 16.2.2.3 short PPDU: 72 us preamble + 24 us header at 2 Mb/s; ns-3 uses
  // it for 5.5 and 11 Mb/s only (GetPreambleForTransmission).
  const PhyMode cck11 = ModeFor(Standard::k80211b, 11);
  const PhyHeader short_header = HeaderFor(Standard::k80211b, cck11, true);
  EXPECT_EQ(short_header.preamble_and_header_ns, 96 * kNsPerUs);
  EXPECT_EQ(short_header.header_mode.rate_mbps, 2);
  EXPECT_EQ(PpduDurationNs(cck11, short_header, 1536), (96 + 1118) * kNsPerUs);
  const PhyMode dqpsk = ModeFor(Standard::k80211b, 2);
  EXPECT_EQ(HeaderFor(Standard::k80211b, dqpsk, true).preamble_and_header_ns, 192 * kNsPerUs);
}

TEST(PhyModeTest, NoiseFloorAndReferenceLossDefaults) {
  // docs/references.md#radio-defaults: -93.97 dBm over 20 MHz with NF 7; Friis at 1 m 46.6777 dB
  // (5.15 GHz) and 40.046 dB (2.4 GHz).
  MediumConfig a;
  const PhyInfo pa = DerivePhyInfo(a);
  EXPECT_NEAR(pa.noise_floor_dbm, -93.97, 0.005);
  EXPECT_NEAR(pa.reference_loss_db, 46.6777, 0.0005);
  MediumConfig g;
  g.standard = Standard::k80211g;
  EXPECT_NEAR(DerivePhyInfo(g).reference_loss_db, 40.046, 0.0005);
}

TEST(PhyModeTest, EthernetFrameGrowsBy22BytesOnAir) { EXPECT_EQ(MpduBytesForEthernet(1514), 1536); }

}  // namespace
}  // namespace sitlnet::mac

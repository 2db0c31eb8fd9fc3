// The table-based error model against ns-3 3.37: the PER tables of its
// TableBasedErrorRateModel (src/wifi/model/reference/error-rate-tables.h,
// values typed in here), the expected values of its own test suite
// (wifi-error-rate-models-test.cc, TableBasedErrorRateTestCase: MCS 0 at 1,
// 1000 and 2000 bytes) and values ns-3 itself returned for the 9 Mb/s
// fallback (`ns3_side_by_side error-rates`, which also sweeps every rate,
// SNRs in 0.01 dB steps and 16 chunk sizes: largest difference 0).
#include <gtest/gtest.h>

#include <cmath>

#include "mac_phy_sim/error_rate.h"
#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {
namespace {

constexpr auto kTable = MediumConfig::ErrorModel::kTableBased;

double Linear(double db) { return std::pow(10.0, db / 10); }

double Per(double rate_mbps, double snr_db, double bytes) {
  return 1 -
         ChunkSuccessRate(kTable, ModeFor(Standard::k80211a, rate_mbps), Linear(snr_db), 8 * bytes);
}

struct TablePoint {
  double rate_mbps, snr_db, per;
};

// Three points of the cliff of each MCS table (MCS 0-6 are 6, 12, 18, 24,
// 36, 48, 54 Mb/s); a chunk of exactly the table's size gets the table's PER.
TEST(TableErrorRateTest, LargeFramesMatchNs3Tables) {
  const TablePoint points[] = {
      {6, 0.0, 0.8185},   {6, 1.0, 0.0663},   {6, 2.0, 0.0015},   {12, 3.0, 0.7944},
      {12, 4.0, 0.0728},  {12, 5.0, 0.0015},  {18, 5.5, 0.7578},  {18, 6.5, 0.0676},
      {18, 7.5, 0.0023},  {24, 8.5, 0.8405},  {24, 10.0, 0.0374}, {24, 11.0, 0.0019},
      {36, 11.5, 0.9269}, {36, 13.0, 0.0465}, {36, 14.0, 0.0026}, {48, 15.5, 0.9479},
      {48, 17.0, 0.1058}, {48, 18.5, 0.0023}, {54, 17.0, 0.8796}, {54, 18.5, 0.0639},
      {54, 20.0, 0.0013},
  };
  for (const TablePoint& p : points) {
    EXPECT_NEAR(Per(p.rate_mbps, p.snr_db, 1458), p.per, 1e-12)
        << p.rate_mbps << " Mb/s at " << p.snr_db << " dB";
  }
}

TEST(TableErrorRateTest, SmallFramesMatchNs3Tables) {
  const TablePoint points[] = {
      {6, -2.5, 0.9408},  {6, -0.5, 0.1254},  {6, 1.0, 0.0015},   {12, 0.5, 0.9671},
      {12, 2.5, 0.1182},  {12, 4.0, 0.0016},  {18, 3.0, 0.9588},  {18, 5.0, 0.1171},
      {18, 6.5, 0.0016},  {24, 5.5, 0.969},   {24, 7.5, 0.2571},  {24, 9.5, 0.0032},
      {36, 9.0, 0.9479},  {36, 11.0, 0.1572}, {36, 13.0, 0.0011}, {48, 12.5, 0.9653},
      {48, 15.0, 0.1575}, {48, 17.0, 0.0023}, {54, 14.0, 0.9625}, {54, 16.5, 0.1145},
      {54, 18.5, 0.0016},
  };
  for (const TablePoint& p : points) {
    EXPECT_NEAR(Per(p.rate_mbps, p.snr_db, 32), p.per, 1e-12)
        << p.rate_mbps << " Mb/s at " << p.snr_db << " dB";
  }
}

// ns-3's own expectations (tolerance 1e-5 as there): interpolation between
// table points, the scaling 1 - (1 - PER)^(size / 1458) for 1000 and 2000
// bytes, and the 32-byte table scaled down to one byte.
TEST(TableErrorRateTest, ScalingMatchesNs3TestSuite) {
  const struct {
    double bytes, snr_db, per;
  } cases[] = {
      {1458, -0.25, 0.90625}, {1458, 0.25, 0.55465}, {1458, 2.75, 0.00008}, {1000, -0.25, 0.80280},
      {1000, 0.25, 0.42581},  {1000, 1.75, 0.00436}, {2000, 0.25, 0.67031}, {2000, 1.25, 0.05277},
      {2000, 2.75, 0.00011},  {1, -3.25, 0.17075},   {1, -3.00, 0.15260},   {1, -2.25, 0.06494},
      {1458, -1.25, 1.0},     {1458, 3.25, 0.0},
  };
  for (const auto& c : cases) {
    EXPECT_NEAR(Per(6, c.snr_db, c.bytes), c.per, 1e-5) << c.bytes << " B at " << c.snr_db << " dB";
  }
}

// Chunks under 400 bytes use the 32-byte table (ns-3's SizeThreshold): a
// 399-byte chunk at 1 dB is 1 - (1 - 0.0015)^(399/32), a 400-byte one
// 1 - (1 - 0.0663)^(400/1458).
TEST(TableErrorRateTest, SizeThresholdPicksTheTable) {
  EXPECT_NEAR(Per(6, 1.0, 399), 1 - std::pow(1 - 0.0015, 399.0 / 32), 1e-12);
  EXPECT_NEAR(Per(6, 1.0, 400), 1 - std::pow(1 - 0.0663, 400.0 / 1458), 1e-12);
}

// SNRs are rounded to 0.01 dB before the lookup, and PERs under 1e-5 are 0.
TEST(TableErrorRateTest, RoundsSnrAndSmallPers) {
  EXPECT_EQ(Per(6, 1.004, 1458), Per(6, 1.0, 1458));
  EXPECT_NE(Per(6, 1.006, 1458), Per(6, 1.0, 1458));
  EXPECT_NEAR(Per(6, 3.0, 1458), 0.00001, 1e-12);  // At the precision: kept.
  EXPECT_EQ(Per(6, 3.0, 1000), 0.0);               // 6.9e-6 after scaling: 0.
}

// 9 Mb/s (BPSK 3/4) has no table; ns-3 falls back to its Yans model. Values
// ns-3 3.37 returned for a 1539-byte chunk (12312 bits).
TEST(TableErrorRateTest, NineMbpsFallsBackToYansAsNs3) {
  const PhyMode mode = ModeFor(Standard::k80211a, 9);
  const struct {
    double snr_db, success;
  } cases[] = {{2, 0.298241567}, {3, 0.887840821}, {4, 0.993241297}, {5, 0.999804211}};
  for (const auto& c : cases) {
    EXPECT_NEAR(ChunkSuccessRate(kTable, mode, Linear(c.snr_db), 12312), c.success, 1e-9);
  }
}

TEST(TableErrorRateTest, DsssUsesTheSameFormulasAsNist) {
  for (double rate : {1.0, 2.0, 5.5, 11.0}) {
    const PhyMode mode = ModeFor(Standard::k80211b, rate);
    for (double snr_db : {-2.0, 0.0, 2.0, 4.0}) {
      EXPECT_EQ(ChunkSuccessRate(kTable, mode, Linear(snr_db), 8000),
                ChunkSuccessRate(mode, Linear(snr_db), 8000));
    }
  }
}

// The hot path skips the model above PerfectSinr: it must hold for every
// chunk size of both tables, and be the smallest such SINR.
TEST(TableErrorRateTest, PerfectSinrHoldsForEveryChunkSize) {
  for (double rate : {6.0, 9.0, 12.0, 18.0, 24.0, 36.0, 48.0, 54.0}) {
    const PhyMode mode = ModeFor(Standard::k80211a, rate);
    const double perfect = PerfectSinr(kTable, mode);
    for (double bytes : {1.0, 3.0, 32.0, 200.0, 399.0, 400.0, 1458.0, 2000.0, 2400.0}) {
      EXPECT_EQ(ChunkSuccessRate(kTable, mode, perfect, 8 * bytes), 1.0) << rate << " " << bytes;
    }
    const bool below_fails = ChunkSuccessRate(kTable, mode, perfect / 1.01, 8 * 2400) < 1.0 ||
                             ChunkSuccessRate(kTable, mode, perfect / 1.01, 8 * 399) < 1.0;
    EXPECT_TRUE(below_fails) << rate;
  }
}

}  // namespace
}  // namespace sitlnet::mac

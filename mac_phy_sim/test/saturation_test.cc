// Saturation throughput and collision probability against ns-3's Bianchi
// reference tables and Bianchi's model (docs/references.md#bianchi).
//
// Duration: ns-3 measures 100 s. What matters for an honest 1.5 % check is
// the number of delivered frames, not seconds: each test measures about
// 25,000 frames (10 s at 54 Mb/s, 64 s at 6 Mb/s of virtual time; < 0.3 s
// of wall time each). Over four to six seeds the throughput of one
// configuration varied with a standard deviation of 0.1-0.3 %, so the 1.5 %
// band is at least five standard deviations wide around a mean error that is
// itself within 1 % of the DIFS table: a pass or fail reflects the model, not
// the sampling. The seed is fixed, so the outcome is reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac::testing {
namespace {

TimeNs MeasureFor(int frames, double expected_mbps) {
  return static_cast<TimeNs>(frames * 1500.0 * 8 / (expected_mbps * 1e6) * 1e9);
}

struct OneStationCase {
  double rate_mbps;
  double expected_mbps;  // Analytic, basic access, no collisions (docs/validation.md).
};

class OneStationTest : public ::testing::TestWithParam<OneStationCase> {};

TEST_P(OneStationTest, MatchesAnalyticThroughput) {
  SaturationSetup setup;
  setup.stations = 1;
  setup.topology = Topology::kSink;
  setup.rate_mbps = GetParam().rate_mbps;
  setup.measure_ns = MeasureFor(25000, GetParam().expected_mbps);
  const SaturationResult result = RunSaturation(setup);
  // Only the backoff draw is random: its standard deviation is 4.6 slots per
  // frame, about 0.07 % of the throughput over 25,000 frames.
  EXPECT_NEAR(result.throughput_mbps, GetParam().expected_mbps, 0.004 * GetParam().expected_mbps);
  EXPECT_EQ(result.collision_probability, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Rates, OneStationTest,
                         ::testing::Values(OneStationCase{54, 30.4956}, OneStationCase{24, 17.6082},
                                           OneStationCase{12, 10.0209}, OneStationCase{6, 5.3727}));

struct BianchiCase {
  int stations;
  double rate_mbps;
  Topology topology;
  double difs_table_mbps;
  double eifs_table_mbps;
};

std::string Name(const ::testing::TestParamInfo<BianchiCase>& info) {
  return std::string(info.param.topology == Topology::kRing ? "Ring" : "Sink") + "N" +
         std::to_string(info.param.stations) + "Rate" +
         std::to_string(static_cast<int>(info.param.rate_mbps));
}

class BianchiTest : public ::testing::TestWithParam<BianchiCase> {};

TEST_P(BianchiTest, WithinNs3PassRule) {
  const BianchiCase& c = GetParam();
  SaturationSetup setup;
  setup.stations = c.stations;
  setup.rate_mbps = c.rate_mbps;
  setup.topology = c.topology;
  setup.measure_ns = MeasureFor(25000, c.eifs_table_mbps);
  const SaturationResult result = RunSaturation(setup);
  // ns-3's rule: min(|error vs DIFS table|, |error vs EIFS table|) <= 1.5 %.
  const double error_difs = std::fabs(result.throughput_mbps / c.difs_table_mbps - 1);
  const double error_eifs = std::fabs(result.throughput_mbps / c.eifs_table_mbps - 1);
  EXPECT_LE(std::min(error_difs, error_eifs), 0.015)
      << "measured " << result.throughput_mbps << " Mb/s over " << result.frames_delivered
      << " frames; DIFS table " << c.difs_table_mbps << ", EIFS table " << c.eifs_table_mbps;
}

// ns-3's Bianchi reference tables (docs/references.md#bianchi).
constexpr BianchiCase kCases[] = {
    {5, 6, Topology::kRing, 4.7087, 4.6899},    {10, 6, Topology::kRing, 4.3453, 4.3197},
    {5, 24, Topology::kRing, 16.2470, 16.0836}, {10, 24, Topology::kRing, 15.1426, 14.9153},
    {5, 54, Topology::kRing, 29.8324, 29.2861}, {10, 54, Topology::kRing, 28.1519, 27.3763},
    {5, 6, Topology::kSink, 4.7087, 4.6899},    {10, 6, Topology::kSink, 4.3453, 4.3197},
    {5, 24, Topology::kSink, 16.2470, 16.0836}, {10, 24, Topology::kSink, 15.1426, 14.9153},
    {5, 54, Topology::kSink, 29.8324, 29.2861}, {10, 54, Topology::kSink, 28.1519, 27.3763},
};

INSTANTIATE_TEST_SUITE_P(Ns3Tables, BianchiTest, ::testing::ValuesIn(kCases), Name);

// Bianchi's fixed point: tau = 2(1-2p) / [(1-2p)(W+1) + pW(1-(2p)^m)],
// p = 1 - (1-tau)^(n-1), solved by bisection on p.
double BianchiP(int n, int w, int m) {
  auto residual = [&](double p) {
    const double tau = 2 * (1 - 2 * p) / ((1 - 2 * p) * (w + 1) + p * w * (1 - std::pow(2 * p, m)));
    return 1 - std::pow(1 - tau, n - 1) - p;
  };
  double lo = 1e-9, hi = 0.499999;
  for (int i = 0; i < 100; ++i) {
    const double mid = (lo + hi) / 2;
    (residual(mid) > 0 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

TEST(BianchiModelTest, FixedPointMatchesReference) {
  // docs/references.md#bianchi: W = 16, m = 6: n = 5 p = 0.27154, n = 10 p = 0.38440.
  EXPECT_NEAR(BianchiP(5, 16, 6), 0.27154, 5e-5);
  EXPECT_NEAR(BianchiP(10, 16, 6), 0.38440, 5e-5);
}

TEST(CollisionProbabilityTest, CloseToBianchiP) {
  // Bianchi's chain decrements the counter in every slot, including the one
  // in which a transmission starts, and assumes a constant, independent p;
  // the standard (and ns-3, and this model) resumes counting only after DIFS
  // of idle medium, and colliders resume DIFS after their ACK timeout (SIFS +
  // slot + 20 us after the frame) while the others resume DIFS after the
  // frames. This lowers p slightly: 4-7 % below the model at n = 10, 3.5-6 %
  // at n = 5. Tolerance: 8 % relative.
  for (int n : {5, 10}) {
    SaturationSetup setup;
    setup.stations = n;
    setup.rate_mbps = 54;
    setup.measure_ns = 10 * kNsPerS;
    const SaturationResult result = RunSaturation(setup);
    const double expected = BianchiP(n, 16, 6);
    EXPECT_NEAR(result.collision_probability, expected, 0.08 * expected) << "n=" << n;
  }
}

}  // namespace
}  // namespace sitlnet::mac::testing

// Student's t quantiles against published tables and closed forms; sample statistics by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// Upper 2.5 % critical values, NIST/SEMATECH e-Handbook of Statistical Methods, 1.3.6.7.2
// ("Critical values of the Student's t distribution"), printed to 3 decimals.
TEST(StudentTTest, MatchesThePublishedTableAt975) {
  const struct {
    int dof;
    double t;
  } table[] = {{1, 12.706}, {2, 4.303},  {3, 3.182},  {4, 2.776},  {5, 2.571},  {9, 2.262},
               {10, 2.228}, {19, 2.093}, {20, 2.086}, {30, 2.042}, {60, 2.000}, {100, 1.984}};
  for (const auto& row : table) {
    EXPECT_NEAR(StudentTQuantile(0.975, row.dof), row.t, 5e-4) << row.dof;
  }
}

TEST(StudentTTest, MatchesThePublishedTableAt95And995) {
  EXPECT_NEAR(StudentTQuantile(0.95, 1), 6.314, 5e-4);
  EXPECT_NEAR(StudentTQuantile(0.95, 10), 1.812, 5e-4);
  EXPECT_NEAR(StudentTQuantile(0.995, 5), 4.032, 5e-4);
  EXPECT_NEAR(StudentTQuantile(0.995, 20), 2.845, 5e-4);
}

// One degree of freedom is Cauchy: t = tan(pi (p - 1/2)); two: t = (2p - 1) / sqrt(2 p (1 - p)).
TEST(StudentTTest, MatchesTheClosedFormsForOneAndTwoDegrees) {
  for (double p : {0.6, 0.9, 0.975, 0.999}) {
    EXPECT_NEAR(StudentTQuantile(p, 1), std::tan(std::numbers::pi * (p - 0.5)), 1e-9) << p;
    EXPECT_NEAR(StudentTQuantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-9) << p;
  }
}

TEST(StudentTTest, IsSymmetricAndTendsToTheNormal) {
  EXPECT_DOUBLE_EQ(StudentTQuantile(0.025, 7), -StudentTQuantile(0.975, 7));
  EXPECT_EQ(StudentTQuantile(0.5, 3), 0);
  EXPECT_NEAR(StudentTQuantile(0.975, 1000000), 1.959964, 1e-5);  // The normal's z(0.975).
}

// 1..5: mean 3, sd sqrt(2.5), half-width t(0.975, 4) sd / sqrt(5) with the table's 2.776.
TEST(SummarizeTest, ComputesMeanSdAndIntervalByHand) {
  const SampleSummary summary = Summarize({1, 2, 3, 4, 5});
  EXPECT_EQ(summary.n, 5);
  EXPECT_DOUBLE_EQ(summary.mean, 3);
  EXPECT_DOUBLE_EQ(summary.standard_deviation, std::sqrt(2.5));
  EXPECT_NEAR(summary.ci95_half_width, 2.776 * std::sqrt(2.5) / std::sqrt(5.0), 1e-3);
}

TEST(SummarizeTest, LeavesSpreadUndefinedBelowTwoSamples) {
  const SampleSummary one = Summarize({4});
  EXPECT_EQ(one.n, 1);
  EXPECT_EQ(one.mean, 4);
  EXPECT_TRUE(std::isnan(one.standard_deviation));
  EXPECT_TRUE(std::isnan(one.ci95_half_width));
  EXPECT_EQ(Summarize({}).n, 0);
  EXPECT_TRUE(std::isnan(Summarize({}).mean));
}

}  // namespace
}  // namespace sitlnet::sweep

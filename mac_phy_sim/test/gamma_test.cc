// The fading samplers (gamma.h) against their distributions: Kolmogorov-Smirnov against the
// normal CDF and the Gamma CDF (the regularized incomplete gamma function, computed here
// independently of any sampler), tail frequencies of the normal, and a sampler of a
// deliberately wrong shape that the same test must reject.
#include "mac_phy_sim/gamma.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace sitlnet::mac {
namespace {

// Regularized lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a): the series for
// x < a + 1, else 1 - the continued fraction for Q(a, x) by the modified Lentz method
// (Press et al., Numerical Recipes, 3rd ed., 6.2).
double GammaCdf(double a, double x) {
  if (x <= 0) return 0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 10000 && std::fabs(term) > std::fabs(sum) * 1e-16; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefix);
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1) < 1e-16) break;
  }
  return 1 - std::exp(log_prefix) * h;
}

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// Kolmogorov-Smirnov statistic of `samples` against `cdf`.
double KsStatistic(std::vector<double> samples, const std::function<double(double)>& cdf) {
  std::sort(samples.begin(), samples.end());
  const double n = static_cast<double>(samples.size());
  double d = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const double f = cdf(samples[i]);
    d = std::max({d, f - i / n, (i + 1) / n - f});
  }
  return d;
}

constexpr int kSamples = 100000;
// The KS critical value at the 0.1 % level: 1.95 / sqrt(n) (0.0062 here).
const double kCritical = 1.95 / std::sqrt(static_cast<double>(kSamples));

TEST(GammaTest, IncompleteGammaMatchesClosedForms) {
  // a = 1: 1 - e^-x; a = 2: 1 - e^-x (1 + x); a = 0.5: erf(sqrt(x)).
  for (const double x : {0.01, 0.3, 1.0, 2.5, 7.0, 30.0}) {
    EXPECT_NEAR(GammaCdf(1, x), 1 - std::exp(-x), 1e-13) << x;
    EXPECT_NEAR(GammaCdf(2, x), 1 - std::exp(-x) * (1 + x), 1e-13) << x;
    EXPECT_NEAR(GammaCdf(0.5, x), std::erf(std::sqrt(x)), 1e-13) << x;
  }
}

TEST(GammaTest, NormalFollowsItsCdfAndTails) {
  RandomEngine rng(20240615);
  std::vector<double> samples(kSamples);
  for (double& x : samples) x = StandardNormal(rng);
  EXPECT_LT(KsStatistic(samples, NormalCdf), kCritical);
  // The tails, where KS sees little: beyond the ziggurat's base r = 3.654 (its tail
  // algorithm) and further out. 4,000,000 draws; tolerances 5 standard errors.
  const int draws = 4000000;
  int beyond_r = 0, beyond_4_5 = 0, negative = 0;
  for (int i = 0; i < draws; ++i) {
    const double x = StandardNormal(rng);
    beyond_r += std::fabs(x) > 3.6541528853610088;
    beyond_4_5 += std::fabs(x) > 4.5;
    negative += x < 0;
  }
  const auto check = [&](int count, double p, const char* what) {
    const double expected = draws * p, sd = std::sqrt(draws * p * (1 - p));
    EXPECT_NEAR(count, expected, 5 * sd) << what;
  };
  check(beyond_r, std::erfc(3.6541528853610088 / std::sqrt(2.0)), "|x| > r");
  check(beyond_4_5, std::erfc(4.5 / std::sqrt(2.0)), "|x| > 4.5");
  check(negative, 0.5, "x < 0");
}

std::vector<double> GammaSamples(double shape, uint64_t seed) {
  const GammaSampler sampler(shape);
  RandomEngine rng(seed);
  std::vector<double> samples(kSamples);
  for (double& x : samples) x = sampler.Draw(rng);
  return samples;
}

TEST(GammaTest, GammaFollowsTheGammaCdf) {
  // 0.5 and 0.75 go through the boost (shape + 1 and U^(1/shape)), 1 and up do not.
  for (const double shape : {0.5, 0.75, 1.0, 1.5, 3.0}) {
    const std::vector<double> samples = GammaSamples(shape, 7 + static_cast<uint64_t>(shape * 4));
    const double d = KsStatistic(samples, [&](double x) { return GammaCdf(shape, x); });
    EXPECT_LT(d, kCritical) << "shape " << shape;
    double sum = 0;
    for (double x : samples) sum += x;
    // Mean = shape, variance = shape: 5 standard errors.
    EXPECT_NEAR(sum / kSamples, shape, 5 * std::sqrt(shape / kSamples)) << "shape " << shape;
  }
}

TEST(GammaTest, TheKsTestRejectsAWrongShape) {
  // A sampler 5 % off in shape fails the test the right one passes (D is 3.4 to 6.6 times
  // the critical value here).
  for (const double shape : {0.5, 0.75, 1.0, 1.5, 3.0}) {
    const std::vector<double> samples = GammaSamples(shape * 1.05, 99);
    const double d = KsStatistic(samples, [&](double x) { return GammaCdf(shape, x); });
    EXPECT_GT(d, kCritical) << "shape " << shape;
  }
}

TEST(GammaTest, BaseBoundsTheBoostedDraw) {
  // Shape < 1: Draw = Base (a Gamma(shape + 1) draw) * U^(1/shape) <= Base, and the two
  // steps consume the stream as Draw does.
  const GammaSampler sampler(0.75);
  ASSERT_TRUE(sampler.boosted());
  EXPECT_FALSE(GammaSampler(1.5).boosted());
  RandomEngine a(5), b(5);
  for (int i = 0; i < 1000; ++i) {
    const double base = sampler.Base(a);
    const double draw = base * std::exp(sampler.LogBoost(a));
    EXPECT_LE(draw, base);
    EXPECT_DOUBLE_EQ(sampler.Draw(b), draw);
  }
}

TEST(GammaTest, Log10UpperBoundIsAboveAndClose) {
  RandomEngine rng(11);
  for (int i = 0; i < 200000; ++i) {
    const double x = std::exp(60 * (OpenUniform(rng) - 0.5));  // e^-30 .. e^30
    const double bound = Log10UpperBound(x), exact = std::log10(x);
    ASSERT_GE(bound, exact) << x;
    ASSERT_LE(bound - exact, 0.0017) << x;
  }
  for (const double x : {1.0, 2.0, 0.5, 1 + 1.0 / 256, 1e-320, 1e300}) {
    EXPECT_GE(Log10UpperBound(x), std::log10(x)) << x;
  }
}

}  // namespace
}  // namespace sitlnet::mac

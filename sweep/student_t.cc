// Student's t quantiles and sample statistics. Debian 12's Boost.Math (students_t) is not
// installed here, so the quantile is computed: the t CDF is 1 - I_x(dof/2, 1/2) / 2 with
// x = dof / (dof + t^2) for t > 0 (Abramowitz & Stegun 26.7.1, 26.5.27), I_x by its continued
// fraction (A&S 26.5.8, Lentz's evaluation), and the CDF inverted by bisection. Tested against
// published t tables and the closed forms for 1 and 2 degrees of freedom.
#include <cmath>
#include <limits>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// The continued fraction of I_x(a, b) (A&S 26.5.8), converging for x < (a + 1) / (a + b + 2).
double BetaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEpsilon = 1e-15;
  double c = 1;
  double d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1 / d;
  double fraction = d;
  for (int m = 1; m <= 10000; ++m) {
    // The even step d_{2m}, then the odd step d_{2m+1}.
    for (const double numerator :
         {m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
          -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))}) {
      d = 1 + numerator * d;
      if (std::fabs(d) < kTiny) d = kTiny;
      c = 1 + numerator / c;
      if (std::fabs(c) < kTiny) c = kTiny;
      d = 1 / d;
      fraction *= d * c;
      if (std::fabs(d * c - 1) < kEpsilon && numerator < 0) return fraction;
    }
  }
  return fraction;
}

// The regularized incomplete beta function I_x(a, b), x in [0, 1].
double RegularizedIncompleteBeta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double front = std::exp(log_front);
  // The symmetry I_x(a, b) = 1 - I_{1-x}(b, a) keeps the fraction where it converges fast.
  if (x < (a + 1) / (a + b + 2)) return front * BetaContinuedFraction(a, b, x) / a;
  return 1 - front * BetaContinuedFraction(b, a, 1 - x) / b;
}

// P(T <= t) for t >= 0.
double StudentTCdfNonNegative(double t, int dof) {
  const double x = dof / (dof + t * t);
  return 1 - 0.5 * RegularizedIncompleteBeta(0.5 * dof, 0.5, x);
}

}  // namespace

double StudentTQuantile(double p, int dof) {
  SITLNET_DEMAND(p > 0 && p < 1 && dof >= 1);
  if (p < 0.5) return -StudentTQuantile(1 - p, dof);
  if (p == 0.5) return 0;
  double low = 0, high = 1;
  while (StudentTCdfNonNegative(high, dof) < p) {
    low = high;
    high *= 2;
    SITLNET_DEMAND(std::isfinite(high));
  }
  // Bisection to the double's resolution: the CDF is monotone, so this cannot miss.
  for (int i = 0; i < 200 && high - low > 1e-14 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (StudentTCdfNonNegative(middle, dof) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

SampleSummary Summarize(const std::vector<double>& samples) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  SampleSummary summary;
  summary.n = static_cast<int>(samples.size());
  if (summary.n == 0) return {0, kNaN, kNaN, kNaN};
  double sum = 0;
  for (double sample : samples) sum += sample;
  summary.mean = sum / summary.n;
  if (summary.n < 2) {
    summary.standard_deviation = summary.ci95_half_width = kNaN;
    return summary;
  }
  double squares = 0;
  for (double sample : samples) squares += (sample - summary.mean) * (sample - summary.mean);
  summary.standard_deviation = std::sqrt(squares / (summary.n - 1));
  summary.ci95_half_width = StudentTQuantile(0.975, summary.n - 1) * summary.standard_deviation /
                            std::sqrt(static_cast<double>(summary.n));
  return summary;
}

}  // namespace sitlnet::sweep

// Student's t quantiles (Boost.Math's students_t, Debian's libboost-dev, header-only) and sample
// statistics. Tested against published t tables and the closed forms for 1 and 2 degrees of
// freedom (test/student_t_test.cc).
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {

double StudentTQuantile(double p, int dof) {
  SITLNET_DEMAND(p > 0 && p < 1 && dof >= 1);
  return boost::math::quantile(boost::math::students_t_distribution<double>(dof), p);
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

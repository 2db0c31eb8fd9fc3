#include "mac_phy_sim/test/fading_statistics.h"

#include <cmath>
#include <functional>
#include <numbers>

namespace sitlnet::mac {

FadingSamples SampleJakesProcesses(const JakesParameters& parameters, int processes,
                                   TimeNs step_ns, int steps, uint64_t seed) {
  FadingSamples samples;
  samples.step_s = static_cast<double>(step_ns) / kNsPerS;
  RandomEngine rng(seed);
  for (int k = 0; k < processes; ++k) {
    const JakesProcess process(parameters, rng);
    auto& x = samples.gains.emplace_back();
    for (int j = 0; j < steps; ++j) x.push_back(process.ComplexGain(j * step_ns));
  }
  return samples;
}

namespace {

// Mean and standard error over processes of a per-process mean.
Estimate OverProcesses(const FadingSamples& samples,
                       const std::function<double(const std::vector<std::complex<double>>&)>& f) {
  const size_t n = samples.gains.size();
  double sum = 0, sum_squares = 0;
  for (const auto& process : samples.gains) {
    const double value = f(process);
    sum += value;
    sum_squares += value * value;
  }
  Estimate e;
  e.mean = sum / n;
  const double variance = n > 1 ? (sum_squares - n * e.mean * e.mean) / (n - 1) : 0;
  e.standard_error = std::sqrt(std::max(variance, 0.0) / n);
  return e;
}

}  // namespace

Estimate MeanPowerGain(const FadingSamples& samples) {
  return OverProcesses(samples, [](const std::vector<std::complex<double>>& x) {
    double sum = 0;
    for (const std::complex<double>& g : x) sum += std::norm(g) / 2;
    return sum / x.size();
  });
}

Estimate Autocorrelation(const FadingSamples& samples, int lag_steps) {
  return OverProcesses(samples, [lag_steps](const std::vector<std::complex<double>>& x) {
    const size_t n = x.size() - lag_steps;
    double sum = 0;
    for (size_t t = 0; t < n; ++t) sum += (x[t] * std::conj(x[t + lag_steps])).real() / 2;
    return sum / n;
  });
}

FadeStatistics FadesBelow(const FadingSamples& samples, double power_gain_threshold) {
  long crossings = 0, steps_below = 0, steps = 0;
  for (const auto& x : samples.gains) {
    bool below = std::norm(x[0]) / 2 < power_gain_threshold;
    for (size_t t = 1; t < x.size(); ++t) {
      const bool now_below = std::norm(x[t]) / 2 < power_gain_threshold;
      if (now_below && !below) ++crossings;
      if (now_below) ++steps_below;
      below = now_below;
    }
    steps += static_cast<long>(x.size()) - 1;
  }
  FadeStatistics f;
  f.crossings_per_s = crossings / (steps * samples.step_s);
  f.mean_fade_s = crossings > 0 ? steps_below * samples.step_s / crossings : 0;
  return f;
}

double RayleighCrossingsPerS(double doppler_hz, double rho) {
  return std::sqrt(2 * std::numbers::pi) * doppler_hz * rho * std::exp(-rho * rho);
}

double RayleighMeanFadeS(double doppler_hz, double rho) {
  return (std::exp(rho * rho) - 1) / (rho * doppler_hz * std::sqrt(2 * std::numbers::pi));
}

}  // namespace sitlnet::mac

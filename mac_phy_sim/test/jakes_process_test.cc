// The Jakes process against its definition (Zheng & Xiao 2003, as ns-3 3.37 implements it):
// autocorrelation J0(2 pi f_d tau), mean power 1, level crossings and fade durations against
// Rayleigh's closed forms, the 2 M bound, and the pair table's symmetry and order independence.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "mac_phy_sim/jakes_fading.h"
#include "mac_phy_sim/jakes_process.h"
#include "mac_phy_sim/test/fading_statistics.h"

namespace sitlnet::mac {
namespace {

// `processes` independent processes sampled every `step_ns` for `duration_ns`.
FadingSamples Sample(const JakesParameters& parameters, int processes, TimeNs step_ns,
                     TimeNs duration_ns, uint64_t seed) {
  return SampleJakesProcesses(parameters, processes, step_ns,
                              static_cast<int>((duration_ns + step_ns - 1) / step_ns), seed);
}

double J0(double x) { return std::cyl_bessel_j(0.0, x); }

// 200 processes over 1 s, every 0.25 ms, lags 0-20 ms (J0 down to its second zero at 80 Hz).
// Averaged over time, one process's autocorrelation is (1/M) sum_n cos(w_n tau): only theta
// varies between processes, and its mean over theta is J0 exactly. The measured standard error
// is at most 0.0027 (asserted below 0.003): the 0.01 tolerance is over 3.5 of them, while a
// Doppler 2 % off moves the curve by up to 0.05 at these lags (checked: it fails the rule).
TEST(JakesProcessTest, AutocorrelationIsBesselJ0) {
  const JakesParameters parameters;  // ns-3's defaults: 80 Hz, 20 oscillators.
  const TimeNs step_ns = 250 * kNsPerUs;
  const FadingSamples samples = Sample(parameters, 200, step_ns, kNsPerS, 7);
  double worst = 0, worst_if_doppler_off = 0, largest_error = 0;
  for (int lag = 0; lag <= 80; lag += 2) {
    const Estimate r = Autocorrelation(samples, lag);
    const double x = 2 * std::numbers::pi * parameters.doppler_hz * lag * samples.step_s;
    EXPECT_NEAR(r.mean, J0(x), 0.01) << "lag " << lag * samples.step_s * 1e3 << " ms";
    EXPECT_LT(r.standard_error, 0.003);
    largest_error = std::max(largest_error, r.standard_error);
    worst = std::max(worst, std::abs(r.mean - J0(x)));
    worst_if_doppler_off = std::max(worst_if_doppler_off, std::abs(r.mean - J0(1.02 * x)));
  }
  EXPECT_GT(worst_if_doppler_off, 0.01) << "the rule cannot tell a 2 % Doppler error";
  std::printf(
      "autocorrelation: largest |R - J0| %.4f (%.4f against a Doppler 2 %% off), largest "
      "standard error %.4f\n",
      worst, worst_if_doppler_off, largest_error);
}

// Time-averaged, each process's power is sum |a_n|^2 / 4 = 1 (distinct frequencies); over a
// finite 1 s the cross terms leave a few percent per process, under 0.01 over 100.
TEST(JakesProcessTest, MeanPowerGainIsOne) {
  const FadingSamples samples = Sample(JakesParameters{}, 100, 250 * kNsPerUs, kNsPerS, 8);
  const Estimate power = MeanPowerGain(samples);
  EXPECT_NEAR(power.mean, 1.0, 0.01);
  const FadingSamples slow = Sample(JakesParameters{5, 8}, 100, 2 * kNsPerMs, 10 * kNsPerS, 9);
  EXPECT_NEAR(MeanPowerGain(slow).mean, 1.0, 0.02);
}

// Sampled finely enough that few fades fall between two samples (a fade at -10 dB lasts 1.7
// ms at 80 Hz, 0.66 ms at 200 Hz: over 30 samples): about 5,000 fades at 0 dB and 3,500 at
// -10 dB each, so counting alone is off by 1.5-2 %; the sum of 20 oscillators is close to, not
// exactly, Gaussian. Rule: 5 %.
TEST(JakesProcessTest, FadesMatchRayleighClosedForms) {
  struct Case {
    JakesParameters parameters;
    int processes;
    TimeNs step_ns, duration_ns;
  };
  for (const Case& c : {Case{{80, 20}, 100, 50 * kNsPerUs, kNsPerS},
                        Case{{200, 20}, 50, 20 * kNsPerUs, kNsPerS / 2}}) {
    const FadingSamples samples = Sample(c.parameters, c.processes, c.step_ns, c.duration_ns, 10);
    for (const double threshold_db : {0.0, -10.0}) {
      const double rho = std::pow(10.0, threshold_db / 20);
      const FadeStatistics fades = FadesBelow(samples, rho * rho);
      const double crossings = RayleighCrossingsPerS(c.parameters.doppler_hz, rho);
      const double fade_s = RayleighMeanFadeS(c.parameters.doppler_hz, rho);
      EXPECT_NEAR(fades.crossings_per_s / crossings, 1, 0.05)
          << c.parameters.doppler_hz << " Hz, " << threshold_db << " dB";
      EXPECT_NEAR(fades.mean_fade_s / fade_s, 1, 0.05)
          << c.parameters.doppler_hz << " Hz, " << threshold_db << " dB";
      std::printf("%g Hz, %g dB: %.2f crossings/s (closed form %.2f), fade %.3f ms (%.3f)\n",
                  c.parameters.doppler_hz, threshold_db, fades.crossings_per_s, crossings,
                  fades.mean_fade_s * 1e3, fade_s * 1e3);
    }
  }
}

// FastCos against std::cos over its whole domain (small, large and negative phases).
TEST(JakesProcessTest, FastCosIsCos) {
  RandomEngine rng(12);
  double worst = 0;
  for (const double scale : {1.0, 10.0, 1e3, 1e6, kFastCosLimitRad}) {
    for (int k = 0; k < 100000; ++k) {
      const double x = scale * (2 * OpenUniform(rng) - 1);
      worst = std::max(worst, std::abs(FastCos(x) - std::cos(x)));
    }
  }
  EXPECT_LT(worst, 1e-14);
  std::printf("largest |FastCos - cos|: %.3g\n", worst);
}

TEST(JakesProcessTest, PowerGainNeverExceedsTwoM) {
  RandomEngine rng(11);
  for (const int m : {4, 20, 100}) {
    const double bound_db = JakesProcess::MaxPowerGainDb(m);
    EXPECT_DOUBLE_EQ(bound_db, 10 * std::log10(2.0 * m));
    for (int k = 0; k < 20; ++k) {
      const JakesProcess process(JakesParameters{80, m}, rng);
      for (TimeNs t = 0; t < kNsPerS; t += 500 * kNsPerUs) {
        ASSERT_LE(process.PowerGainDb(t), bound_db + 1e-9);
      }
    }
  }
}

// ns-3's PropagationCache ignores the order of the pair: one process serves both directions.
// Each pair's process comes from the seed and the pair alone, whatever was used before.
TEST(JakesFadingTest, OneProcessPerUnorderedPairIndependentOfUseOrder) {
  JakesFading first({80, 20}, 42), second({80, 20}, 42), other_seed({80, 20}, 43);
  const TimeNs t = 123456789;
  const double g01 = first.PowerGainDb(0, 1, t);
  EXPECT_EQ(first.PowerGainDb(1, 0, t), g01);
  const double g23 = first.PowerGainDb(2, 3, t);
  EXPECT_EQ(second.PowerGainDb(3, 2, t), g23);
  EXPECT_EQ(second.PowerGainDb(0, 1, t), g01);
  EXPECT_NE(other_seed.PowerGainDb(0, 1, t), g01);
  EXPECT_NE(g01, g23);
  EXPECT_EQ(first.process_count(), 2u);
}

}  // namespace
}  // namespace sitlnet::mac

// Statistics of sampled complex fading gains, shared by the unit tests and the side-by-side
// program against ns-3 (bench/ns3_reference/ns3_jakes.cc), so both sides are measured alike;
// and the closed forms they are compared with.
#ifndef SITLNET_MAC_PHY_SIM_TEST_FADING_STATISTICS_H_
#define SITLNET_MAC_PHY_SIM_TEST_FADING_STATISTICS_H_

#include <complex>
#include <cstdint>
#include <vector>

#include "mac_phy_sim/jakes_process.h"

namespace sitlnet::mac {

// Complex gains X of independent processes, each sampled every `step_s` from time 0.
struct FadingSamples {
  double step_s = 0;
  std::vector<std::vector<std::complex<double>>> gains;  // [process][step].
};

// `processes` independent Jakes processes of mac_phy_sim, drawn in turn from one engine seeded
// with `seed`, each sampled `steps` times every `step_ns` from time 0.
FadingSamples SampleJakesProcesses(const JakesParameters& parameters, int processes,
                                   TimeNs step_ns, int steps, uint64_t seed);

// A mean over processes and its standard error (spread of the per-process means / sqrt(n)).
struct Estimate {
  double mean = 0;
  double standard_error = 0;
};

// Mean power gain |X|^2 / 2.
Estimate MeanPowerGain(const FadingSamples& samples);
// Normalised autocorrelation Re(X(t) X*(t + lag)) / 2 at lag `lag_steps` x step_s: averaged
// over t within each process, then over processes.
Estimate Autocorrelation(const FadingSamples& samples, int lag_steps);

// Fades below a power gain threshold rho^2 (rho: envelope over its rms value).
struct FadeStatistics {
  double crossings_per_s = 0;  // Downward crossings of the threshold per second.
  double mean_fade_s = 0;      // Time below the threshold per downward crossing.
};
FadeStatistics FadesBelow(const FadingSamples& samples, double power_gain_threshold);

// Rayleigh fading with the Clarke/Jakes Doppler spectrum (Rappaport, "Wireless
// Communications", 2nd ed., 5.7.3): level-crossing rate sqrt(2 pi) f_d rho exp(-rho^2) and
// average fade duration (exp(rho^2) - 1) / (rho f_d sqrt(2 pi)).
double RayleighCrossingsPerS(double doppler_hz, double rho);
double RayleighMeanFadeS(double doppler_hz, double rho);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_TEST_FADING_STATISTICS_H_

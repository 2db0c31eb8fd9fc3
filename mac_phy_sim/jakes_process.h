// Time-correlated Rayleigh fading of one station pair: ns-3 3.37's JakesProcess
// (src/propagation/model/jakes-process.cc), the sum-of-sinusoids model of Zheng & Xiao,
// "Simulation Models With Correct Statistical Properties for Rayleigh Fading Channels",
// IEEE Trans. Commun. 51(6), 920-928, 2003. The complex gain is
//   X(t) = 2 / sqrt(M) * sum_n exp(j psi_n) cos(w_d cos(alpha_n) t + phi),
//   alpha_n = (2 pi n - pi + theta) / (4 M), n = 1..M,
// with theta, phi and every psi_n uniform in [-pi, pi) and w_d = 2 pi f_d. As in ns-3, phi and
// theta are shared by the M oscillators (Zheng & Xiao draw a phi per oscillator); averaged over
// theta and the psi_n, E[X(t) X*(t + tau)] / 2 is J0(w_d tau) exactly (docs/mac_phy_sim.md).
// The power gain is |X|^2 / 2: mean 1, at most 2 M.
#ifndef SITLNET_MAC_PHY_SIM_JAKES_PROCESS_H_
#define SITLNET_MAC_PHY_SIM_JAKES_PROCESS_H_

#include <complex>
#include <vector>

#include "common/common.h"
#include "mac_phy_sim/gamma.h"

namespace sitlnet::mac {

// ns-3 3.37 JakesProcess's attributes, with its defaults and its checker's ranges.
struct JakesParameters {
  double doppler_hz = 80;  // Maximum Doppler f_d: (0, 1e4] (ns-3 asserts f_d != 0).
  int oscillators = 20;    // M: [4, 1000].
};

class JakesProcess {
 public:
  // Draws phi, theta, then psi_1..psi_M from `rng`, in ns-3's order.
  JakesProcess(const JakesParameters& parameters, RandomEngine& rng);

  // X at virtual time `at_ns` (ns-3 evaluates it at Simulator::Now(), from time 0).
  std::complex<double> ComplexGain(TimeNs at_ns) const;
  // 10 log10(|X|^2 / 2) at `at_ns`: the dB added to the received power.
  double PowerGainDb(TimeNs at_ns) const;
  // The same with w_d t replaced by a Doppler phase: the integral of w_d over time when the
  // Doppler changes (jakes_doppler.h). Each oscillator turns by cos(alpha_n) times it.
  std::complex<double> ComplexGainAtPhase(double doppler_phase_rad) const;
  double PowerGainDbAtPhase(double doppler_phase_rad) const;
  // 10 log10(2 M): no power gain of an M-oscillator process exceeds it (|X| <= 2 sqrt(M)).
  static double MaxPowerGainDb(int oscillators);

 private:
  // One array per quantity, so the sum over oscillators vectorises.
  std::vector<double> cos_alpha_;        // cos(alpha_n): oscillator n turns at w_d cos(alpha_n).
  std::vector<double> amplitude_re_;     // 2 / sqrt(M) cos(psi_n).
  std::vector<double> amplitude_im_;     // 2 / sqrt(M) sin(psi_n).
  double phase_rad_ = 0;                 // phi, shared.
  double omega_max_rad_per_s_ = 0;       // w_d.
};

// cos(x) for |x| <= kFastCosLimitRad, within 1e-14 of std::cos and several times cheaper:
// x less the nearest multiple of 2 pi (Cody & Waite's reduction, 2 pi in two parts), then
// cos's Taylor series to degree 28 (its remainder is under 1e-17 on [-pi, pi]). Inline and
// branch-free so that a loop of them vectorises.
inline constexpr double kFastCosLimitRad = 8e8;  // Below 2^27 * 2 pi: k * kTwoPiHigh is exact.
inline double FastCos(double x) {
  constexpr double kTwoPiHigh = 0x1.921fb58000000p+2;   // 2 pi to 26 bits.
  constexpr double kTwoPiLow = -0x1.dde973dcb3b3ap-25;  // 2 pi - kTwoPiHigh.
  constexpr double kRound = 0x1.8p52;                    // Adding it rounds to an integer.
  const double k = (x * (1 / (2 * 3.14159265358979323846)) + kRound) - kRound;
  const double r = (x - k * kTwoPiHigh) - k * kTwoPiLow;
  const double u = r * r;
  double sum = 3.279889237069838e-30;  // 1 / 28!, then down to 1 / 0!, alternating signs.
  for (const double c : {-2.4795962632247976e-27, 1.6117375710961184e-24,
                         -8.896791392450574e-22, 4.110317623312165e-19, -1.5619206968586225e-16,
                         4.779477332387385e-14, -1.1470745597729725e-11, 2.08767569878681e-09,
                         -2.755731922398589e-07, 2.48015873015873e-05, -0.001388888888888889,
                         0.041666666666666664, -0.5, 1.0}) {
    sum = sum * u + c;
  }
  return sum;
}

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_JAKES_PROCESS_H_

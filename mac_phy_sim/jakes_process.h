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
  // 10 log10(2 M): no power gain of an M-oscillator process exceeds it (|X| <= 2 sqrt(M)).
  static double MaxPowerGainDb(int oscillators);

 private:
  struct Oscillator {
    std::complex<double> amplitude;  // 2 / sqrt(M) * exp(j psi_n).
    double omega_rad_per_s = 0;      // w_d cos(alpha_n).
  };
  double phase_rad_ = 0;  // phi, shared.
  std::vector<Oscillator> oscillators_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_JAKES_PROCESS_H_

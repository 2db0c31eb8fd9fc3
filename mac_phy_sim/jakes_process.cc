#include "mac_phy_sim/jakes_process.h"

#include <cmath>
#include <numbers>

namespace sitlnet::mac {
namespace {

// ns-3's JakesPropagationLossModel draws every angle from one UniformRandomVariable set to
// [-pi, pi).
double UniformAngleRad(RandomEngine& rng) {
  return -std::numbers::pi + 2 * std::numbers::pi * OpenUniform(rng);
}

}  // namespace

JakesProcess::JakesProcess(const JakesParameters& parameters, RandomEngine& rng) {
  SITLNET_DEMAND(parameters.doppler_hz > 0 && parameters.doppler_hz <= 1e4);
  SITLNET_DEMAND(parameters.oscillators >= 4 && parameters.oscillators <= 1000);
  const int m = parameters.oscillators;
  const double omega_max_rad_per_s = 2 * std::numbers::pi * parameters.doppler_hz;
  phase_rad_ = UniformAngleRad(rng);
  const double theta_rad = UniformAngleRad(rng);
  const double amplitude = 2.0 / std::sqrt(static_cast<double>(m));
  omega_max_rad_per_s_ = omega_max_rad_per_s;
  for (int n = 1; n <= m; ++n) {
    const double alpha_rad = (2 * std::numbers::pi * n - std::numbers::pi + theta_rad) / (4.0 * m);
    const double psi_rad = UniformAngleRad(rng);
    cos_alpha_.push_back(std::cos(alpha_rad));
    amplitude_re_.push_back(amplitude * std::cos(psi_rad));
    amplitude_im_.push_back(amplitude * std::sin(psi_rad));
  }
}

std::complex<double> JakesProcess::ComplexGain(TimeNs at_ns) const {
  // As ns-3's Time::GetSeconds().
  return ComplexGainAtPhase(omega_max_rad_per_s_ * (static_cast<double>(at_ns) / 1e9));
}

std::complex<double> JakesProcess::ComplexGainAtPhase(double doppler_phase_rad) const {
  const size_t m = cos_alpha_.size();
  double re = 0, im = 0;
  if (std::abs(doppler_phase_rad) + std::numbers::pi <= kFastCosLimitRad) {
    for (size_t n = 0; n < m; ++n) {
      const double c = FastCos(cos_alpha_[n] * doppler_phase_rad + phase_rad_);
      re += amplitude_re_[n] * c;
      im += amplitude_im_[n] * c;
    }
  } else {  // After 19 days at 80 Hz, 3.7 hours at 10 kHz.
    for (size_t n = 0; n < m; ++n) {
      const double c = std::cos(cos_alpha_[n] * doppler_phase_rad + phase_rad_);
      re += amplitude_re_[n] * c;
      im += amplitude_im_[n] * c;
    }
  }
  return {re, im};
}

double JakesProcess::PowerGainDb(TimeNs at_ns) const {
  return 10 * std::log10(std::norm(ComplexGain(at_ns)) / 2);
}

double JakesProcess::PowerGainDbAtPhase(double doppler_phase_rad) const {
  return 10 * std::log10(std::norm(ComplexGainAtPhase(doppler_phase_rad)) / 2);
}

double JakesProcess::MaxPowerGainDb(int oscillators) { return 10 * std::log10(2.0 * oscillators); }

}  // namespace sitlnet::mac

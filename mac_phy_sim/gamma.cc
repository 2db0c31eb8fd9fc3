#include "mac_phy_sim/gamma.h"

#include <cmath>

namespace sitlnet::mac {
namespace {

// Ziggurat for the half-normal density f(x) = exp(-x^2 / 2) (unnormalised), 256 layers of
// equal area v. Layer 0 is the base strip [0, x[0]] x [0, f(r)] (x[0] = v / f(r): the
// rectangle part plus, virtually, the tail beyond r); layer i >= 1 is [0, x[i]] x [f(x[i]),
// f(x[i + 1])], with x[1] = r, x[i + 1] = f^-1(f(x[i]) + v / x[i]) and x[256] = 0.
// r = 3.6541528853610088 for 256 layers (Marsaglia & Tsang 2000, Doornik 2005); v follows
// from r: r f(r) + the tail area sqrt(pi / 2) erfc(r / sqrt(2)). The top layer then has
// area v to 1e-13 relative (checked when written).
ZigguratTables MakeZiggurat() {
  constexpr int kLayers = ZigguratTables::kLayers;
  constexpr double kR = ZigguratTables::kR;
  ZigguratTables z;
  const double fr = std::exp(-0.5 * kR * kR);
  const double v = kR * fr + std::sqrt(M_PI / 2) * std::erfc(kR / std::sqrt(2.0));
  z.x[0] = v / fr;
  z.x[1] = kR;
  for (int i = 1; i < kLayers - 1; ++i) {
    z.x[i + 1] = std::sqrt(-2 * std::log(std::exp(-0.5 * z.x[i] * z.x[i]) + v / z.x[i]));
  }
  z.x[kLayers] = 0;
  for (int i = 0; i <= kLayers; ++i) z.f[i] = std::exp(-0.5 * z.x[i] * z.x[i]);
  return z;
}

Log10Table MakeLog10Table() {
  Log10Table table;
  for (int k = 0; k < 256; ++k) table.upper[k] = std::log10(1 + (k + 1) / 256.0) + 1e-12;
  return table;
}

}  // namespace

const ZigguratTables kZiggurat = MakeZiggurat();
const Log10Table kLog10Table = MakeLog10Table();

double NormalSlowPath(RandomEngine& rng, uint64_t bits) {
  constexpr double kR = ZigguratTables::kR;
  while (true) {
    // `bits` failed its layer's inner rectangle: layer i, sign and uniform as in StandardNormal.
    const int i = static_cast<int>(bits & 0xff);
    const bool negative = (bits & 0x100) != 0;
    double x = static_cast<double>(bits >> 11) * 0x1.0p-53 * kZiggurat.x[i];
    if (x < kZiggurat.x[i + 1]) return negative ? -x : x;
    if (i == 0) {
      // Base strip beyond r: the tail (Marsaglia 1964).
      double y;
      do {
        x = -std::log(OpenUniform(rng)) / kR;
        y = -std::log(OpenUniform(rng));
      } while (2 * y < x * x);
      return negative ? -(kR + x) : kR + x;
    }
    // Wedge between x[i + 1] and x[i]: accept under the curve.
    const double y = kZiggurat.f[i] + OpenUniform(rng) * (kZiggurat.f[i + 1] - kZiggurat.f[i]);
    if (y < std::exp(-0.5 * x * x)) return negative ? -x : x;
    bits = rng();  // Rejected: start over.
  }
}

GammaSampler::GammaSampler(double shape) : shape_(shape), boosted_(shape < 1) {
  const double base_shape = boosted_ ? shape + 1 : shape;
  d_ = base_shape - 1.0 / 3;
  c_ = 1 / std::sqrt(9 * d_);
  inverse_shape_ = 1 / shape;
}

bool GammaSampler::LogTestAccepts(double u, double x2, double v) const {
  return std::log(u) < 0.5 * x2 + d_ * (1 - v + std::log(v));
}

double GammaSampler::Boost(RandomEngine& rng) const { return std::exp(LogBoost(rng)); }

double GammaSampler::LogBoost(RandomEngine& rng) const {
  return std::log(OpenUniform(rng)) * inverse_shape_;
}

}  // namespace sitlnet::mac

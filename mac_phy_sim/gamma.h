// Exact Gamma and normal variates for the fading model (medium_state.h), cheaper than
// libstdc++'s std::gamma_distribution (Marsaglia-Tsang over a polar-method normal, with a
// pow for shape < 1) and without hidden state, so one sampler per shape serves every station.
//
// Normal: the ziggurat of Marsaglia & Tsang, "The Ziggurat Method for Generating Random
// Variables", J. Stat. Softw. 5(8), 2000, with 256 layers and the independent-bits layout of
// Doornik, "An Improved Ziggurat Method to Generate Normal Random Samples", 2005: one 64-bit
// draw gives the layer (8 bits), the sign (1 bit) and a 53-bit uniform; the tail beyond R
// is drawn as in Marsaglia, "Generating a Variable from the Tail of the Normal
// Distribution", Technometrics 6(1), 1964.
// Gamma: Marsaglia & Tsang, "A Simple Method for Generating Gamma Variables", ACM TOMS
// 26(3), 2000, for shape >= 1; for shape < 1 their boost Gamma(a) = Gamma(a + 1) * U^(1/a)
// (section 6 of the paper), split in two steps so a caller that only needs to know whether
// the draw exceeds a threshold can stop after the first (Gamma(a + 1) bounds the result).
#ifndef SITLNET_MAC_PHY_SIM_GAMMA_H_
#define SITLNET_MAC_PHY_SIM_GAMMA_H_

#include <bit>
#include <cmath>
#include <cstdint>

namespace sitlnet::mac {

// SplitMix64 (Steele, Lea and Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA
// 2014): one 64-bit mix, for decorrelated seeds and hashes from a seed and an index.
inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// xoshiro256++ (Blackman & Vigna, "Scrambled Linear Pseudorandom Number Generators", ACM
// TOMS 47(4), 2021; the reference code at prng.di.unimi.it), its state filled from a 64-bit
// seed by SplitMix64 as the authors recommend. A UniformRandomBitGenerator; about 5 times
// cheaper per number than std::mt19937_64 here, with 32 bytes of state instead of 2.5 kB.
class Xoshiro256PlusPlus {
 public:
  using result_type = uint64_t;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }

  explicit Xoshiro256PlusPlus(uint64_t seed = 1) { this->seed(seed); }
  void seed(uint64_t seed) {
    for (uint64_t& word : s_) {
      seed += 0x9E3779B97F4A7C15ull;
      uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      word = z ^ (z >> 31);
    }
  }
  result_type operator()() {
    const uint64_t result = Rotl(s_[0] + s_[3], 23) + s_[0];
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }

 private:
  static uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

using RandomEngine = Xoshiro256PlusPlus;

// Uniform in (0, 1): 53 random bits, centred in their interval (never 0 or 1).
inline double OpenUniform(RandomEngine& rng) {
  return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
}

// The ziggurat's tables (gamma.cc), filled before main.
struct ZigguratTables {
  static constexpr int kLayers = 256;
  static constexpr double kR = 3.6541528853610088;  // Right edge of the base layer.
  double x[kLayers + 1];  // Layer edges, x[0] > x[1] = kR > ... > x[256] = 0.
  double f[kLayers + 1];  // exp(-x^2 / 2) at them.
};
extern const ZigguratTables kZiggurat;

// The base strip beyond r and the wedges (gamma.cc): the slow path of StandardNormal.
double NormalSlowPath(RandomEngine& rng, uint64_t bits);

// Standard normal N(0, 1) (ziggurat): one 64-bit draw in about 99 % of the calls.
inline double StandardNormal(RandomEngine& rng) {
  const uint64_t bits = rng();
  const int i = static_cast<int>(bits & 0xff);
  const double x = static_cast<double>(bits >> 11) * 0x1.0p-53 * kZiggurat.x[i];
  if (x < kZiggurat.x[i + 1]) return (bits & 0x100) != 0 ? -x : x;  // Inner rectangle.
  return NormalSlowPath(rng, bits);
}

// Gamma(shape, 1) for a fixed shape >= 0.5 (any shape > 0 works; the medium allows >= 0.5).
class GammaSampler {
 public:
  GammaSampler() : GammaSampler(1) {}
  explicit GammaSampler(double shape);

  double shape() const { return shape_; }
  double inverse_shape() const { return inverse_shape_; }
  // Shape < 1: Draw() is Base() * Boost() and Base() >= Draw().
  bool boosted() const { return boosted_; }

  // A Gamma(shape, 1) variate.
  double Draw(RandomEngine& rng) const {
    const double base = Base(rng);
    return boosted_ ? base * Boost(rng) : base;
  }
  // First step: Gamma(shape, 1) if not boosted, else Gamma(shape + 1, 1). Marsaglia & Tsang
  // 2000, section 4: d v for v = (1 + c x)^3, x normal, accepted with the squeeze
  // u < 1 - 0.0331 x^4 or else log u < x^2 / 2 + d (1 - v + log v).
  double Base(RandomEngine& rng) const {
    while (true) {
      double x, v;
      do {
        x = StandardNormal(rng);
        v = 1 + c_ * x;
      } while (v <= 0);
      v = v * v * v;
      const double u = OpenUniform(rng);
      const double x2 = x * x;
      if (u < 1 - 0.0331 * x2 * x2 || LogTestAccepts(u, x2, v)) return d_ * v;
    }
  }
  // Second step (boosted only): U^(1/shape), U uniform in (0, 1).
  double Boost(RandomEngine& rng) const;
  // The same as a natural logarithm, log(U) / shape (<= 0).
  double LogBoost(RandomEngine& rng) const;

 private:
  bool LogTestAccepts(double u, double x2, double v) const;

  double shape_ = 1;
  bool boosted_ = false;
  double d_ = 0, c_ = 0;  // Marsaglia-Tsang: d = a - 1/3, c = 1 / sqrt(9 d), a = the base shape.
  double inverse_shape_ = 1;
};

// An upper bound of log10(x), at most 0.0017 above it (0.017 dB in 10 log10): the binary
// exponent plus log10 at the upper end of the mantissa's 1/256-wide bucket (a table, with
// 1e-12 added for rounding). For a threshold that only has to be on the safe side: a few
// times cheaper than std::log10, with a short dependency chain.
struct Log10Table {
  double upper[256];  // log10(1 + (k + 1) / 256) + 1e-12.
};
extern const Log10Table kLog10Table;

inline double Log10UpperBound(double x) {
  if (!(x >= 0x1.0p-1000 && x <= 0x1.0p1000)) return std::log10(x);  // Far out: exactly.
  const uint64_t bits = std::bit_cast<uint64_t>(x);
  const int exponent = static_cast<int>(bits >> 52) - 1023;
  return exponent * 0.30102999566398120 + 1e-12 + kLog10Table.upper[(bits >> 44) & 0xff];
}

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_GAMMA_H_

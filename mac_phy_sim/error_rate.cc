#include "mac_phy_sim/error_rate.h"

#include <algorithm>
#include <cmath>

#include "mac_phy_sim/table_error_rate.h"

namespace sitlnet::mac {
namespace {

// Uncoded bit error rates on AWGN (Proakis), as the NIST model takes them.
double UncodedBer(Modulation modulation, double sinr) {
  switch (modulation) {
    case Modulation::kBpsk:
      return 0.5 * std::erfc(std::sqrt(sinr));
    case Modulation::kQpsk:
      return 0.5 * std::erfc(std::sqrt(sinr / 2.0));
    case Modulation::kQam16:
      return 0.75 * 0.5 * std::erfc(std::sqrt(sinr / (5.0 * 2.0)));
    case Modulation::kQam64:
      return 7.0 / 12.0 * 0.5 * std::erfc(std::sqrt(sinr / (21.0 * 2.0)));
    case Modulation::kQam256:
      // ns-3's general square M-QAM: (sqrt(M) - 1) / (sqrt(M) log2 sqrt(M)) erfc(sqrt(3 snr /
      // (2 (M - 1)))), M = 256: 15/64 erfc(sqrt(snr / 170)).
      return 15.0 / 64.0 * std::erfc(std::sqrt(sinr / 170.0));
    default:
      return 0.5;
  }
}

// Union bound on the decoded bit error probability of the 802.11 K=7
// convolutional code for input BER p (hard decisions): sum over distances d
// of c_d * D^d with D = sqrt(4 p (1 - p)), scaled by 1/(2b) for punctured
// codes. Spectra: rate 1/2 (d_free 10), 2/3 (d_free 6), 3/4 (d_free 5), and
// 5/6 (d_free 4) as ns-3 3.37's NistErrorRateModel::CalculatePe has it.
double DecodedBitError(double p, int code_rate_b) {
  const double d = std::sqrt(4.0 * p * (1.0 - p));
  auto series = [d](int first_distance, int step, std::initializer_list<double> weights) {
    double sum = 0;
    // Integer powers by multiplication: std::pow is the hot spot otherwise.
    double power = 1;
    for (int i = 0; i < first_distance; ++i) power *= d;
    const double multiplier = step == 1 ? d : d * d;
    for (double weight : weights) {
      sum += weight * power;
      power *= multiplier;
    }
    return sum;
  };
  switch (code_rate_b) {
    case 1:
      return 0.5 * series(10, 2,
                          {36.0, 211.0, 1404.0, 11633.0, 77433.0, 502690.0, 3322763.0, 21292910.0,
                           134365911.0});
    case 2:
      return 1.0 / 4.0 *
             series(6, 1,
                    {3.0, 70.0, 285.0, 1276.0, 6160.0, 27128.0, 117019.0, 498860.0, 2103891.0,
                     8784123.0});
    case 5:
      return 1.0 / 10.0 *
             series(4, 1,
                    {92.0, 528.0, 8694.0, 79453.0, 792114.0, 7375573.0, 67884974.0, 610875423.0,
                     5427275376.0, 47664215639.0});
    default:
      return 1.0 / 6.0 *
             series(5, 1,
                    {42.0, 201.0, 1492.0, 10469.0, 62935.0, 379644.0, 2253373.0, 13073811.0,
                     75152755.0, 428005675.0});
  }
}

// DQPSK bit error approximation used by ns-3's DsssErrorRateModel.
double DqpskBer(double ebn0) {
  return ((std::sqrt(2.0) + 1.0) / std::sqrt(8.0 * M_PI * std::sqrt(2.0))) *
         (1.0 / std::sqrt(ebn0)) * std::exp(-(2.0 - std::sqrt(2.0)) * ebn0);
}

// Symbol error probability of 8 bi-orthogonal... as ns-3 (GSL build) takes
// it for CCK: 1 - integral_{-beta}^{inf} (2 Phi(x + beta) - 1)^(n-1) phi(x) dx,
// beta = sqrt(2 e), n = 8. Trapezoid rule; the integrand vanishes beyond 12.
double CckSymbolErrorProb16(double e) {
  const double beta = std::sqrt(2.0 * e);
  const int steps = 2000;
  const double lo = -beta, hi = 12.0;
  const double h = (hi - lo) / steps;
  double sum = 0;
  for (int i = 0; i <= steps; ++i) {
    const double x = lo + i * h;
    const double phi_cdf = 0.5 * std::erfc(-(x + beta) / std::sqrt(2.0));
    const double value =
        std::pow(2 * phi_cdf - 1, 7.0) * std::exp(-x * x / 2) / std::sqrt(2 * M_PI);
    sum += (i == 0 || i == steps) ? value / 2 : value;
  }
  return std::clamp(1.0 - sum * h, 0.0, 1.0);
}

}  // namespace

double ChunkSuccessRate(const PhyMode& mode, double sinr, double bits) {
  if (bits <= 0) return 1.0;
  switch (mode.modulation) {
    case Modulation::kDbpsk: {
      const double ebn0 = sinr * 22.0;  // 11-chip Barker at 1 Msym/s over 22 MHz.
      return std::pow(1.0 - 0.5 * std::exp(-ebn0), bits);
    }
    case Modulation::kDqpsk: {
      const double ebn0 = sinr * 22.0 / 2.0;
      return std::pow(1.0 - std::min(1.0, DqpskBer(ebn0)), bits);
    }
    case Modulation::kCck55: {
      const double ebn0 = sinr * 22.0 / 1.375 / 4.0;
      return std::pow(1.0 - CckSymbolErrorProb16(4.0 * ebn0 / 2.0), bits / 4.0);
    }
    case Modulation::kCck11: {
      const double ebn0 = sinr * 22.0 / 1.375 / 8.0;
      const double sep16 = CckSymbolErrorProb16(8.0 * ebn0 / 2.0 / 2.0);
      return std::pow((1.0 - sep16) * (1.0 - sep16), bits / 8.0);
    }
    default:
      break;
  }
  const double ber = UncodedBer(mode.modulation, sinr);
  if (ber == 0.0) return 1.0;
  const double pe = std::min(1.0, DecodedBitError(ber, mode.code_rate_b));
  return std::pow(1.0 - pe, bits);
}

double ChunkSuccessRate(MediumConfig::ErrorModel model, const PhyMode& mode, double sinr,
                        double bits) {
  if (model == MediumConfig::ErrorModel::kTableBased && mode.ofdm) {
    return TableBasedChunkSuccessRate(mode, sinr, bits);
  }
  return ChunkSuccessRate(mode, sinr, bits);
}

double PerfectSinr(MediumConfig::ErrorModel model, const PhyMode& mode) {
  // Bisection in dB between -10 and 80 dB for the smallest SINR where the
  // chunks that fail most easily are certain: 2400 bytes, and for the table
  // model also 399 bytes, the largest chunk its 32-byte table applies to.
  // Success is monotone in SINR and, per table, in size (for NIST the
  // 2400-byte condition implies every smaller one).
  const bool tables = model == MediumConfig::ErrorModel::kTableBased && mode.ofdm;
  auto certain = [&](double sinr) {
    return ChunkSuccessRate(model, mode, sinr, 8.0 * 2400) >= 1.0 &&
           (!tables || ChunkSuccessRate(model, mode, sinr, 8.0 * 399) >= 1.0);
  };
  double lo_db = -10, hi_db = 80;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo_db + hi_db) / 2;
    if (certain(std::pow(10.0, mid / 10))) {
      hi_db = mid;
    } else {
      lo_db = mid;
    }
  }
  return std::pow(10.0, hi_db / 10);
}

}  // namespace sitlnet::mac

#include "mac_phy_sim/table_error_rate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mac_phy_sim/per_tables.h"

namespace sitlnet::mac {
namespace {

// Chunks of at least this many bytes use the 1458-byte table (ns-3's
// SizeThreshold attribute, default 400).
constexpr uint64_t kLargeTableThresholdBytes = 400;
// ns-3's TABLED_BASED_ERROR_MODEL_PRECISION: smaller PERs count as 0.
constexpr double kPerPrecision = 1e-5;

// The MCS whose table applies to a mode; -1: none (BPSK 3/4). HT MCS 8-15 use the curves of
// 0-7 (one stream's), VHT its MCS; legacy OFDM by modulation and code rate (ns-3's GetMcsForMode).
int McsOf(const PhyMode& mode) {
  if (mode.format == PhyFormat::kHt) return mode.mcs % 8;
  if (mode.format == PhyFormat::kVht) return mode.mcs;
  switch (mode.modulation) {
    case Modulation::kBpsk:
      return mode.code_rate_b == 1 ? 0 : -1;
    case Modulation::kQpsk:
      return mode.code_rate_b == 1 ? 1 : 2;
    case Modulation::kQam16:
      return mode.code_rate_b == 1 ? 3 : 4;
    case Modulation::kQam64:
      return mode.code_rate_b == 2 ? 5 : 6;
    default:
      return -1;
  }
}

// The table's PER at `snr_db` (already rounded), linear between points.
double TablePer(const PerTable& table, double snr_db) {
  const double position = (snr_db - table.first_snr_db) / kPerTableStepDb;
  if (position < 0) return 1.0;
  const int below = static_cast<int>(position);
  if (below >= table.size - 1) return 0.0;  // The last point is PER 0.
  const double a = table.per[below], b = table.per[below + 1];
  const double below_db = table.first_snr_db + below * kPerTableStepDb;
  return a + (snr_db - below_db) * (b - a) / kPerTableStepDb;
}

// ns-3's fallback for OFDM BPSK 3/4 (its YansErrorRateModel): hard-decision
// pairwise error probability at the free distance 5 (the sum over the
// majority of wrong bits, i = 3..4 of 5, as ns-3 writes it), times the 8
// error events at that distance, for every bit.
double YansBpsk34SuccessRate(double sinr, uint64_t bits) {
  const double ebn0 = sinr * 20e6 / 12e6;  // Signal spread over the coded (PHY) rate.
  const double ber = 0.5 * std::erfc(std::sqrt(ebn0));
  if (ber == 0.0) return 1.0;
  const double q = 1 - ber;
  const double pd = 10 * ber * ber * ber * q * q + 5 * ber * ber * ber * ber * q;
  const double event = std::min(8 * pd, 1.0);
  return std::pow(1 - event, static_cast<double>(bits));
}

}  // namespace

double TableBasedChunkSuccessRate(const PhyMode& mode, double sinr, double bits) {
  if (bits <= 0) return 1.0;
  // ns-3 truncates rate x duration to whole bits (a tiny chunk may have none
  // and still counts as one byte below).
  const auto whole_bits = static_cast<uint64_t>(bits);
  const int mcs = McsOf(mode);
  if (mcs < 0) return YansBpsk34SuccessRate(sinr, whole_bits);
  const uint64_t bytes = std::max<uint64_t>(1, whole_bits / 8);
  const bool large = bytes >= kLargeTableThresholdBytes;
  const double snr_db = std::floor(10 * std::log10(sinr) * 100 + 0.5) / 100;
  double per = TablePer(BccPerTable(mcs, large), snr_db);
  const uint64_t table_bytes = large ? kLargeTableFrameBytes : kSmallTableFrameBytes;
  if (bytes != table_bytes) {
    per = 1 - std::pow(1 - per, static_cast<double>(bytes) / static_cast<double>(table_bytes));
  }
  return per < kPerPrecision ? 1.0 : 1 - per;
}

}  // namespace sitlnet::mac

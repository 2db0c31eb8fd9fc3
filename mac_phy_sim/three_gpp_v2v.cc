#include "mac_phy_sim/three_gpp_v2v.h"

#include <algorithm>
#include <cmath>

namespace sitlnet::mac {
namespace {

// Vehicle heights of TR 37.885 6.1.2 as ns-3 uses them for the blocker: types 1
// and 2 are 1.6 m, type 3 (trucks) 3 m.
constexpr double kCarHeightM = 1.6;
constexpr double kTruckHeightM = 3.0;

// log10 of the distance, at least 1 m: the formulas go to minus infinity at 0,
// ns-3 does not guard it (docs/mac_phy_sim.md).
double Log10Distance(double distance_m) { return std::log10(std::max(distance_m, 1.0)); }


}  // namespace

double V2vLosLossDb(V2vEnvironment environment, double distance3d_m, double frequency_hz) {
  const double log_d = Log10Distance(distance3d_m), log_f = std::log10(frequency_hz / 1e9);
  if (environment == V2vEnvironment::kUrban) return 38.77 + 16.7 * log_d + 18.2 * log_f;
  return 32.4 + 20 * log_d + 20 * log_f;
}

double V2vNlosLossDb(double distance3d_m, double frequency_hz) {
  return 36.85 + 30 * Log10Distance(distance3d_m) + 18.9 * std::log10(frequency_hz / 1e9);
}

double V2vLosProbability(V2vEnvironment environment, double distance2d_m) {
  const double d = distance2d_m;
  if (environment == V2vEnvironment::kUrban) return std::min(1.0, 1.05 * std::exp(-0.0114 * d));
  if (d <= 475.0) return std::min(1.0, 2.1013e-6 * d * d - 0.002 * d + 1.0193);
  return std::max(0.0, 0.54 - 0.001 * (d - 475.0));
}

double V2vLosUpToM(V2vEnvironment environment, double uniform) {
  const double u = uniform;
  if (environment == V2vEnvironment::kUrban) return std::log(1.05 / u) / 0.0114;
  // Highway: the quadratic falls from 1.0193 at 0 to its minimum 0.5434 near 475.9 m, then
  // p_LOS steps down to the line 0.54 - 0.001 (d - 475), which reaches 0 at 1015 m.
  if (u <= 0.54) return 475.0 + (0.54 - u) / 0.001;
  constexpr double a = 2.1013e-6, b = -0.002, c = 1.0193;
  const double discriminant = b * b - 4 * a * (c - u);
  if (discriminant <= 0) return 475.0;  // u at or under the quadratic's minimum.
  return std::min(475.0, (-b - std::sqrt(discriminant)) / (2 * a));  // The smaller root.
}

double V2vShadowingStdDb(LinkCondition condition) {
  return condition == LinkCondition::kNlos ? 4.0 : 3.0;
}

double V2vShadowingCorrelationM(LinkCondition condition) {
  return condition == LinkCondition::kLos ? 10.0 : 13.0;
}

BlockageMoments V2vBlockageMoments(double distance3d_m, double low_height_m,
                                   double high_height_m, double blocker_height_m) {
  if (low_height_m > blocker_height_m) return {};
  const double growth_db = std::max(0.0, 15 * std::log10(distance3d_m) - 41.0);
  if (high_height_m < blocker_height_m) return {9.0 + growth_db, 4.5};
  return {5.0 + growth_db, 4.0};
}

ThreeGppV2vModel::ThreeGppV2vModel(const ThreeGppV2vParams& params)
    : params_(params),
      // The formulas at 1 m: their frequency terms (log10 1 = 0).
      los_frequency_db_(V2vLosLossDb(params.environment, 1, params.frequency_hz)),
      nlos_frequency_db_(V2vNlosLossDb(1, params.frequency_hz)),
      // dB per decade (16.7 urban, 20 highway; 30 NLOS) over ln(d^2) = 2 ln 10 per decade.
      los_db_per_ln_squared_(
          (V2vLosLossDb(params.environment, 10, params.frequency_hz) - los_frequency_db_) /
          (2 * M_LN10)),
      nlos_db_per_ln_squared_((V2vNlosLossDb(10, params.frequency_hz) - nlos_frequency_db_) /
                              (2 * M_LN10)) {}

size_t ThreeGppV2vModel::PairIndex(int a, int b) {
  const size_t low = static_cast<size_t>(std::min(a, b)), high = static_cast<size_t>(std::max(a, b));
  return high * (high - 1) / 2 + low;
}

double ThreeGppV2vModel::BlockageDb(PairState& pair, double distance3d_m, double low_height_m,
                                    double high_height_m) const {
  // ns-3 ThreeGppV2vUrbanPropagationLossModel::GetAdditionalNlosvLoss: the
  // blocker type first, then max(0, log-normal) with the TR's mean and std.
  const double blocker_height_m =
      OpenUniform(pair.rng) * 100.0 < params_.truck_percent ? kTruckHeightM : kCarHeightM;
  const BlockageMoments m =
      V2vBlockageMoments(distance3d_m, low_height_m, high_height_m, blocker_height_m);
  if (m.std_db == 0) return 0;
  // The log-normal with that mean and std: ln X ~ N(mu, sigma^2).
  const double sigma = std::sqrt(std::log(m.std_db * m.std_db / (m.mean_db * m.mean_db) + 1));
  const double mu = std::log(m.mean_db * m.mean_db /
                             std::sqrt(m.std_db * m.std_db + m.mean_db * m.mean_db));
  return std::max(0.0, std::exp(mu + sigma * StandardNormal(pair.rng)));
}

void ThreeGppV2vModel::UpdateShadowing(PairState& pair, LinkCondition previous,
                                       double relative_x_m, double relative_y_m) const {
  // ns-3 ThreeGppPropagationLossModel::GetShadowing: a new independent value
  // at the first evaluation and when the condition changes; otherwise
  // R s + sqrt(1 - R^2) N std with R = exp(-|change of the 2D relative
  // position| / correlation distance).
  const double std_db = V2vShadowingStdDb(pair.condition);
  // A value that is not a number (a robot was at no position) starts afresh too.
  if (!pair.evaluated || previous != pair.condition || !std::isfinite(pair.shadowing_db)) {
    pair.shadowing_db = StandardNormal(pair.rng) * std_db;
  } else if (relative_x_m != pair.relative_x_m || relative_y_m != pair.relative_y_m) {
    const double moved_x_m = relative_x_m - pair.relative_x_m,
                 moved_y_m = relative_y_m - pair.relative_y_m;
    const double moved_m = std::sqrt(moved_x_m * moved_x_m + moved_y_m * moved_y_m);
    const double r = std::exp(-moved_m / V2vShadowingCorrelationM(pair.condition));
    pair.shadowing_db =
        r * pair.shadowing_db + std::sqrt(1 - r * r) * StandardNormal(pair.rng) * std_db;
  }
  // Else the pair moved together (as a flock in formation): R = 1 keeps the
  // value, as ns-3's formula does, without a draw.
  pair.relative_x_m = relative_x_m;
  pair.relative_y_m = relative_y_m;
}

double ThreeGppV2vModel::LossDb(const PathLossLink& link) {
  const size_t index = PairIndex(link.a, link.b);
  if (index >= pairs_.size()) pairs_.resize(index + 1);
  PairState& pair = pairs_[index];
  const bool a_low = link.a < link.b;
  const Vec3d& low_m = a_low ? link.a_m : link.b_m;
  const Vec3d& high_m = a_low ? link.b_m : link.a_m;
  // ns-3 ThreeGppChannelConditionModel::GetChannelCondition: the condition is computed anew
  // when now - its generation time > UpdatePeriod (strictly), UpdatePeriod 0 meaning never.
  const bool condition_expired = pair.evaluated && params_.update_period_ns > 0 &&
                                 link.now_ns - pair.condition_drawn_ns > params_.update_period_ns;
  if (pair.evaluated && !condition_expired && low_m.x == pair.low_m.x && low_m.y == pair.low_m.y &&
      low_m.z == pair.low_m.z && high_m.x == pair.high_m.x && high_m.y == pair.high_m.y &&
      high_m.z == pair.high_m.z && link.blocked == pair.blocked) {
    return pair.loss_db;  // Nothing moved, no box added across, no redraw due: no new draw.
  }
  // Squared distances: the formulas need log10 d = ln(d^2) / (2 ln 10) and the LOS test
  // compares squares, so most evaluations take no sqrt of a distance.
  const double dx = high_m.x - low_m.x, dy = high_m.y - low_m.y, dz = high_m.z - low_m.z;
  const double distance2d_m2 = dx * dx + dy * dy;
  const double distance3d_m2 = distance2d_m2 + dz * dz;
  // The channel condition (ns-3 ThreeGppChannelConditionModel::ComputeChannelCondition):
  // NLOS when a box blocks the segment (p_NLOS = 1), else LOS if the pair's frozen
  // uniform is at most p_LOS, else NLOSv.
  if (!pair.evaluated) {
    const uint64_t key = (static_cast<uint64_t>(std::min(link.a, link.b)) << 32) |
                         static_cast<uint64_t>(std::max(link.a, link.b));
    // The pair's stream from the model's seed and the pair alone: independent of the
    // order pairs are evaluated in.
    pair.rng.seed(SplitMix64(params_.seed ^ SplitMix64(key)));
  }
  if (!pair.evaluated || condition_expired) {
    pair.condition_uniform = OpenUniform(pair.rng);
    pair.condition_drawn_ns = link.now_ns;
    const double los_up_to_m = V2vLosUpToM(params_.environment, pair.condition_uniform);
    pair.los_up_to_m2 = los_up_to_m * los_up_to_m;
  }
  const LinkCondition previous = pair.condition;
  if (link.blocked) {
    pair.condition = LinkCondition::kNlos;
  } else {
    pair.condition =
        distance2d_m2 <= pair.los_up_to_m2 ? LinkCondition::kLos : LinkCondition::kNlosv;
  }
  // V2vLosLossDb and V2vNlosLossDb with their frequency terms computed once, at least 1 m.
  const double ln_distance_squared = std::log(std::max(distance3d_m2, 1.0));
  const double los_db = los_frequency_db_ + los_db_per_ln_squared_ * ln_distance_squared;
  double loss_db = 0;
  switch (pair.condition) {
    case LinkCondition::kLos:
      loss_db = los_db;
      break;
    case LinkCondition::kNlosv:
      // ns-3 GetLossNlosv: the LOS loss plus the vehicle blockage; heights are
      // min and max z (GetUtAndBsHeights).
      loss_db = los_db + BlockageDb(pair, std::sqrt(distance3d_m2), std::min(low_m.z, high_m.z),
                                    std::max(low_m.z, high_m.z));
      break;
    case LinkCondition::kNlos:
      loss_db = nlos_frequency_db_ + nlos_db_per_ln_squared_ * ln_distance_squared;
      break;
  }
  if (params_.shadowing) {
    UpdateShadowing(pair, previous, dx, dy);
    loss_db += pair.shadowing_db;
  }
  pair.evaluated = true;
  pair.blocked = link.blocked;
  pair.low_m = low_m;
  pair.high_m = high_m;
  pair.loss_db = loss_db;
  return loss_db;
}

}  // namespace sitlnet::mac

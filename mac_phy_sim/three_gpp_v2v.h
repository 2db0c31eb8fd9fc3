// 3GPP TR 37.885 V2V path loss (urban and highway) as ns-3 3.37's
// ThreeGppV2vUrban/HighwayPropagationLossModel with the channel condition of
// ThreeGppV2vUrban/HighwayChannelConditionModel (buildings via
// BuildingsChannelConditionModel) and ThreeGppPropagationLossModel's
// correlated shadowing. Differences from ns-3, and when draws happen, are in
// docs/mac_phy_sim.md ("3GPP TR 37.885 V2V").
#ifndef SITLNET_MAC_PHY_SIM_THREE_GPP_V2V_H_
#define SITLNET_MAC_PHY_SIM_THREE_GPP_V2V_H_

#include <cstdint>
#include <vector>

#include "mac_phy_sim/gamma.h"
#include "mac_phy_sim/path_loss_model.h"

namespace sitlnet::mac {

enum class V2vEnvironment : uint8_t { kUrban, kHighway };
// TR 37.885 6.2.1: line of sight, blocked by vehicles, blocked by buildings.
enum class LinkCondition : uint8_t { kLos, kNlosv, kNlos };

//------------------------- Formulas (pure functions) -------------------------

// LOS path loss, TR 37.885 Table 6.2.1-1, d = 3D distance (m), fc in Hz:
// urban 38.77 + 16.7 log10 d + 18.2 log10 fc_GHz; highway 32.4 + 20 log10 d + 20 log10 fc_GHz.
double V2vLosLossDb(V2vEnvironment environment, double distance3d_m, double frequency_hz);
// NLOS (buildings) path loss, the urban row for both (ns-3's highway inherits it):
// 36.85 + 30 log10 d + 18.9 log10 fc_GHz.
double V2vNlosLossDb(double distance3d_m, double frequency_hz);
// LOS probability against 2D distance (TR 37.885 Table 6.2-1): urban
// min(1, 1.05 exp(-0.0114 d)); highway min(1, 2.1013e-6 d^2 - 0.002 d + 1.0193)
// up to 475 m, then max(0, 0.54 - 0.001 (d - 475)).
double V2vLosProbability(V2vEnvironment environment, double distance2d_m);
// The 2D distance up to which a pair whose frozen uniform is `uniform` in (0, 1) is LOS: p_LOS
// does not increase with distance, so uniform <= p_LOS(d) holds exactly for d up to it.
double V2vLosUpToM(V2vEnvironment environment, double uniform);
// Shadow fading standard deviation (dB) and correlation distance (m), TR 37.885
// Table 6.2.1-1 / 6.2.3-1: 3 dB LOS and NLOSv, 4 dB NLOS; 10 m LOS, 13 m else.
double V2vShadowingStdDb(LinkCondition condition);
double V2vShadowingCorrelationM(LinkCondition condition);
// NLOSv blockage loss's log-normal mean and std (dB) for a blocker of
// `blocker_height_m` (TR 37.885 6.2.1): 0 / 0 if both antennas are above it
// (no loss); 9 + max(0, 15 log10 d - 41) and 4.5 if both are below; else
// 5 + max(0, 15 log10 d - 41) and 4.
struct BlockageMoments {
  double mean_db = 0, std_db = 0;
};
BlockageMoments V2vBlockageMoments(double distance3d_m, double low_height_m,
                                   double high_height_m, double blocker_height_m);

//------------------------------- The model ----------------------------------

struct ThreeGppV2vParams {
  V2vEnvironment environment = V2vEnvironment::kUrban;
  double frequency_hz = 5.15e9;
  bool shadowing = true;      // ns-3's ShadowingEnabled.
  double truck_percent = 0;   // ns-3's PercType3Vehicles: share of 3 m blockers.
  uint64_t seed = 0;          // Of the model's own draws (condition, blockage, shadowing).
  // ns-3's UpdatePeriod of the condition model: a pair's LOS/NLOSv uniform is drawn anew at
  // its first evaluation more than this after the last draw; 0: frozen for the run.
  TimeNs update_period_ns = 0;
};

class ThreeGppV2vModel final : public PathLossModel {
 public:
  explicit ThreeGppV2vModel(const ThreeGppV2vParams& params);
  // Condition, path loss, NLOSv blockage and shadowing of the pair, drawn anew
  // only if a station of the pair moved, or the boxes' blocking changed, since
  // the pair's last evaluation.
  double LossDb(const PathLossLink& link) override;
  bool ComposesWithObstacleShadowing() const override { return false; }
  bool UsesBlockage() const override { return true; }
  bool ChangesWithTime() const override { return params_.update_period_ns > 0; }
  TimeNs RecomputeAfterNs(int a, int b) const override {
    if (params_.update_period_ns == 0) return kNeverNs;
    return Pair(a, b).condition_drawn_ns + params_.update_period_ns;
  }

  // The pair's state after its last evaluation (tests, cause records).
  LinkCondition condition(int a, int b) const { return Pair(a, b).condition; }
  double shadowing_db(int a, int b) const { return Pair(a, b).shadowing_db; }

 private:
  struct PairState {
    bool evaluated = false;
    Vec3d low_m, high_m;  // Positions of the lower and higher station index.
    bool blocked = false;  // PathLossLink::blocked at the last evaluation.
    LinkCondition condition = LinkCondition::kLos;
    double condition_uniform = 0;   // Frozen per pair, or per update period.
    TimeNs condition_drawn_ns = 0;  // When condition_uniform was drawn.
    // The square of V2vLosUpToM for condition_uniform: no exp or sqrt per evaluation.
    double los_up_to_m2 = 0;
    double shadowing_db = 0;
    double relative_x_m = 0, relative_y_m = 0;  // high - low at the last shadowing draw.
    double loss_db = 0;
    RandomEngine rng;  // The pair's own stream, seeded at its first evaluation.
  };
  static size_t PairIndex(int a, int b);
  const PairState& Pair(int a, int b) const {
    SITLNET_DEMAND(PairIndex(a, b) < pairs_.size());  // Evaluated at least once.
    return pairs_[PairIndex(a, b)];
  }
  double BlockageDb(PairState& pair, double distance3d_m, double low_height_m,
                    double high_height_m) const;
  void UpdateShadowing(PairState& pair, LinkCondition previous, double relative_x_m,
                       double relative_y_m) const;

  ThreeGppV2vParams params_;
  // The formulas' frequency terms, constant for the model.
  double los_frequency_db_ = 0, nlos_frequency_db_ = 0;
  // The slopes per unit of ln(d^2): the formulas' dB per decade / (2 ln 10).
  double los_db_per_ln_squared_ = 0, nlos_db_per_ln_squared_ = 0;
  std::vector<PairState> pairs_;  // Lower-triangular: index high (high - 1) / 2 + low.
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_THREE_GPP_V2V_H_

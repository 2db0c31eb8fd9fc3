// Path-loss models: the distance (and height) dependent part of a link's loss,
// one implementation per kind behind PathLossModel, chosen once from the
// MediumConfig (MakePathLossModel). RadioChannel asks the model for a pair's
// loss when it recomputes the pair, then adds obstacle shadowing (if the model
// composes with it) and the fixed log-normal term. The chain and its order are
// described in docs/mac_phy_sim.md ("Path-loss models").
#ifndef SITLNET_MAC_PHY_SIM_PATH_LOSS_MODEL_H_
#define SITLNET_MAC_PHY_SIM_PATH_LOSS_MODEL_H_

#include <cmath>
#include <limits>
#include <memory>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// One station pair as a model sees it. `a` != `b`; the model must give the same
// loss for (a, b) and (b, a).
struct PathLossLink {
  int a = 0, b = 0;   // Station indices.
  Vec3d a_m, b_m;     // Their positions.
  bool blocked = false;  // A box crosses the segment; set only if UsesBlockage().
  TimeNs now_ns = 0;     // The medium's time; read only by models that ChangeWithTime().
};

// "Never" for PathLossModel::RecomputeAfterNs.
constexpr TimeNs kNeverNs = std::numeric_limits<TimeNs>::max();

class PathLossModel {
 public:
  virtual ~PathLossModel() = default;
  // The pair's loss in dB at its current positions. May draw from the model's
  // own seeded streams (3GPP); it draws only when the pair's geometry changed
  // since the last call for the pair, so asking again gives the same value.
  virtual double LossDb(const PathLossLink& link) = 0;
  // True if Sommer obstacle shadowing adds to this model's loss; false if the
  // model accounts for the boxes itself (3GPP's NLOS condition).
  virtual bool ComposesWithObstacleShadowing() const { return true; }
  // True if LossDb needs PathLossLink::blocked.
  virtual bool UsesBlockage() const { return false; }
  // True if a pair's loss may change while neither station moves (3GPP with an update period):
  // the channel then passes the time and asks RecomputeAfterNs.
  virtual bool ChangesWithTime() const { return false; }
  // After LossDb(a, b): the loss stays valid up to and including this time (ns) unless a
  // station moves; kNeverNs if only movement changes it.
  virtual TimeNs RecomputeAfterNs(int /*a*/, int /*b*/) const { return kNeverNs; }
  // True if the loss grows with 3D distance alone, as log-distance, so that a
  // radius bounds the links above a loss (transmission.cc's fading reach).
  virtual bool IsLogDistance() const { return false; }
};

// ns-3 LogDistancePropagationLossModel with d0 = 1 m: reference + 10 n log10(d),
// the reference loss at and below 1 m.
class LogDistanceModel final : public PathLossModel {
 public:
  LogDistanceModel(double reference_loss_db, double exponent)
      : reference_loss_db_(reference_loss_db), exponent_(exponent) {}
  double LossDb(const PathLossLink& link) override;
  bool IsLogDistance() const override { return true; }
  // ns-3 LogDistancePropagationLossModel: the reference loss at or below d0 = 1 m.
  double LossAtDistanceDb(double distance_m) const {
    if (distance_m <= 1.0) return reference_loss_db_;
    return reference_loss_db_ + 10 * exponent_ * std::log10(distance_m);
  }

 private:
  double reference_loss_db_, exponent_;
};

// ns-3 3.37 TwoRayGroundPropagationLossModel: antenna heights are the
// stations' z plus `height_above_z_m`; Friis (with the system loss) up to the
// crossover distance 4 pi ht hr / lambda, then ht^2 hr^2 / (d^4 L); no loss at
// or below `min_distance_m`. `system_loss` is linear, as ns-3's SystemLoss.
struct TwoRayGroundParams {
  double frequency_hz = 5.15e9;  // ns-3's default.
  double height_above_z_m = 0;
  double system_loss = 1;
  double min_distance_m = 0.5;
};
class TwoRayGroundModel final : public PathLossModel {
 public:
  explicit TwoRayGroundModel(const TwoRayGroundParams& params);
  double LossDb(const PathLossLink& link) override;
  // The crossover distance for these antenna heights, in m.
  double CrossoverDistanceM(double tx_height_m, double rx_height_m) const;

 private:
  TwoRayGroundParams params_;
  double lambda_m_;
};

// The model a config asks for (config.path_loss_model), with the frequency and
// reference loss of `phy`.
std::unique_ptr<PathLossModel> MakePathLossModel(const MediumConfig& config, const PhyInfo& phy);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_PATH_LOSS_MODEL_H_

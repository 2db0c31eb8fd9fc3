// RadioChannel: a path-loss model's loss (path_loss_model.h; log-distance by
// default) plus obstacle shadowing after Sommer et al.,
// "A Computationally Inexpensive Empirical Model of IEEE 802.11p Radio
// Shadowing in Urban Environments", WONS 2011: L_obs = beta * walls crossed +
// gamma * metres inside, per box. Loss per station pair is cached and
// recomputed only for stations that moved (or all, after an obstacle is added),
// lazily, when a transmission needs it: the cost follows transmissions x
// stations, not position updates x stations^2.
// A uniform xy grid over the obstacles limits each segment to the boxes in
// the cells it crosses (Amanatides & Woo traversal).
#ifndef SITLNET_MAC_PHY_SIM_CHANNEL_H_
#define SITLNET_MAC_PHY_SIM_CHANNEL_H_

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/path_loss_model.h"

namespace sitlnet::mac {

// Walls crossed and metres inside one box along the segment a -> b (slab
// method in the box frame). Endpoints inside the box cross no wall there.
struct BoxCrossing {
  int walls = 0;
  double inside_m = 0;
};
BoxCrossing CrossBox(const Box& box, const Vec3d& a, const Vec3d& b);

// A box with its rotation and xy bounding rectangle precomputed.
struct PreparedBox {
  Vec3d center_m, half_m;
  double cos_yaw = 1, sin_yaw = 0;
  double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
};
PreparedBox PrepareBox(const Box& box);
BoxCrossing CrossPreparedBox(const PreparedBox& box, const Vec3d& a, const Vec3d& b);

class RadioChannel {
 public:
  // Log-distance path loss (reference loss at 1 m, exponent) with shadowing.
  RadioChannel(double reference_loss_db, double exponent, bool shadowing, double db_per_wall,
               double db_per_m);
  // Any path-loss model (owned). With `shadowing` off, boxes neither add loss
  // nor block the segment for models that use blockage (3GPP's NLOS).
  RadioChannel(std::unique_ptr<PathLossModel> model, bool shadowing, double db_per_wall,
               double db_per_m);

  int AddStation(const Vec3d& position_m);  // Returns its index.
  void SetPosition(int station, const Vec3d& position_m);
  const Vec3d& position(int station) const { return positions_[station]; }
  void AddObstacle(const Box& box);
  int obstacle_count() const { return static_cast<int>(boxes_.size()); }
  // Forgets every cached loss (after the dead-link threshold changed).
  void InvalidateAll() { obstacles_epoch_ = ++epoch_; }
  // The medium's clock (not owned; must outlive the channel). Needed only by a model whose
  // loss ChangesWithTime(): its cached losses are recomputed once the clock passes their
  // RecomputeAfterNs. Without a clock such a model sees time 0.
  void set_clock(const TimeNs* now_ns) { clock_ns_ = now_ns; }

  // Total loss a <-> b in dB (symmetric), recomputed first if stale.
  double LossDb(int a, int b) { return loss_db_[Fresh(a, b)]; }
  // 10^(-LossDb/10): received power = transmitted power * gain (cached too).
  double GainLinear(int a, int b) { return gain_[Fresh(a, b)]; }
  // The loss a <-> b, exact if it is below `stop_db`; otherwise a lower bound
  // >= stop_db (shadowing summed only until the link is certainly that weak).
  // For a caller that knows a tighter threshold than the dead-link loss
  // (fading, transmission.cc); stop_db must not exceed that loss. Exact values
  // go to the cache LossDb uses, bounds to a cache of their own (so LossDb
  // and GainLinear keep their contract).
  double LossDbUntil(int a, int b, double stop_db) {
    const size_t index = static_cast<size_t>(a) * stride_ + b;
    const uint64_t need = NeedEpoch(a, b);
    if (!Expired(index)) {
      if (computed_epoch_[index] >= need) return loss_db_[index];  // Exact, or dead for any stop.
      if (bound_epoch_[index] >= need && bound_db_[index] >= stop_db) return bound_db_[index];
    }
    return RecomputeUntil(a, b, stop_db);
  }
  // The path-loss model's part of LossDb(a, b) at the current positions
  // (a != b); for 3GPP, the values of its last draw if nothing moved since.
  double PathLossDb(int a, int b);
  // Whether a box crosses the segment a -> b (ns-3 BuildingsChannelConditionModel).
  bool SegmentBlocked(const Vec3d& a, const Vec3d& b);
  PathLossModel& path_loss_model() { return *model_; }
  // Uncached: shadowing loss of the segment a -> b; stops adding boxes once
  // the total reaches `stop_at_db` (the link is dead then anyway).
  double ShadowingDb(const Vec3d& a, const Vec3d& b,
                     double stop_at_db = std::numeric_limits<double>::infinity());
  // Losses at or above this are "no link": their exact value is not needed,
  // so shadowing stops accumulating there (see docs/mac_phy_sim.md).
  void set_dead_link_loss_db(double loss_db) { dead_link_loss_db_ = loss_db; }
  // Log-normal shadowing: adds a zero-mean Gaussian loss of `sigma_db` per
  // station pair, the same both ways and for the whole run, drawn from
  // `seed` and the pair alone (independent of the order links are used).
  void set_lognormal_shadowing(double sigma_db, uint64_t seed) {
    lognormal_sigma_db_ = sigma_db;
    lognormal_seed_ = seed;
  }
  // The log-normal loss of pair (a, b) in dB (0 when off).
  double LognormalDb(int a, int b) const;

 private:
  // Index of the pair in the matrices after making it current: a pair is
  // current if computed after both stations last moved and the last obstacle.
  size_t Fresh(int a, int b) {
    const size_t index = static_cast<size_t>(a) * stride_ + b;
    if (computed_epoch_[index] < NeedEpoch(a, b) || Expired(index)) Recompute(a, b);
    return index;
  }
  // True if the model's loss for this pair may have changed with time alone.
  bool Expired(size_t index) const {
    return timed_ && clock_ns_ != nullptr && *clock_ns_ > recompute_after_ns_[index];
  }
  // Records the model's RecomputeAfterNs for both orientations of a freshly computed pair.
  void StoreExpiry(int a, int b);
  uint64_t NeedEpoch(int a, int b) const {
    return std::max({moved_epoch_[a], moved_epoch_[b], obstacles_epoch_});
  }
  void Recompute(int a, int b);
  double RecomputeUntil(int a, int b, double stop_db);
  void Store(int a, int b, double loss);
  void RebuildGrid();
  // A lower bound >= stop_db if the obstacle walk was cut short, else exact
  // (below stop_db exactly so with exact_below_stop; without, it may be an
  // ulp under: Recompute's dead-link contract does not care).
  double ComputeLoss(int a, int b, double stop_db, bool exact_below_stop);
  PathLossLink Link(int a, int b);
  // Calls on_box(box) for every box whose cells the xy projection of a -> b
  // crosses (each once), until done() after a cell.
  template <typename OnBox, typename Done>
  void WalkBoxes(const Vec3d& a, const Vec3d& b, OnBox on_box, Done done);

  std::unique_ptr<PathLossModel> model_;
  // model_ if it is log-distance, else null: the default's loss is computed
  // inline, without the virtual call and the link struct (they cost 2.9 % of
  // the instructions of mac_phy_sim_bench's broadcast row).
  const LogDistanceModel* log_distance_;
  bool obstacle_shadowing_;  // Sommer's loss adds to the model's.
  bool obstacle_blockage_;   // The model needs PathLossLink::blocked.
  bool timed_;               // The model's loss ChangesWithTime().
  const TimeNs* clock_ns_ = nullptr;
  bool shadowing_;
  double db_per_wall_, db_per_m_;
  std::vector<Vec3d> positions_;
  uint64_t epoch_ = 1;                 // Counts changes (moves, obstacles).
  std::vector<uint64_t> moved_epoch_;  // Per station: epoch of its last move.
  uint64_t obstacles_epoch_ = 0;       // Epoch of the last obstacle added.
  double dead_link_loss_db_ = std::numeric_limits<double>::infinity();
  double lognormal_sigma_db_ = 0;
  uint64_t lognormal_seed_ = 0;
  size_t stride_ = 0;
  std::vector<double> loss_db_;           // stride_ x stride_, row-major.
  std::vector<double> gain_;              // Same layout, linear.
  std::vector<uint64_t> computed_epoch_;  // Same layout: epoch when computed (0: never).
  std::vector<TimeNs> recompute_after_ns_;  // Same layout; used only if timed_.
  // LossDbUntil's lower bounds under the dead-link loss, and their epochs (same layout).
  std::vector<double> bound_db_;
  std::vector<uint64_t> bound_epoch_;

  // Obstacles and their grid.
  std::vector<PreparedBox> boxes_;
  bool grid_stale_ = true;
  double grid_x0_ = 0, grid_y0_ = 0, cell_m_ = 1;
  int grid_nx_ = 0, grid_ny_ = 0;
  std::vector<std::vector<int>> cells_;  // Box indices per cell.
  std::vector<uint32_t> visit_stamp_;    // Per box: last query that tested it.
  uint32_t stamp_ = 0;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_CHANNEL_H_

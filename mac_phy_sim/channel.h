// Channel: log-distance path loss plus obstacle shadowing after Sommer et al.,
// "A Computationally Inexpensive Empirical Model of IEEE 802.11p Radio
// Shadowing in Urban Environments", WONS 2011: L_obs = beta * walls crossed +
// gamma * metres inside, per box. Loss per station pair is cached and
// recomputed only for stations that moved (or all, after an obstacle is added).
// A uniform xy grid over the obstacles limits each segment to the boxes in
// the cells it crosses (Amanatides & Woo traversal).
#ifndef SITLNET_MAC_PHY_SIM_CHANNEL_H_
#define SITLNET_MAC_PHY_SIM_CHANNEL_H_

#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// Walls crossed and metres inside one box along the segment a -> b (slab
// method in the box frame). Endpoints inside the box cross no wall there.
struct BoxCrossing {
  int walls = 0;
  double inside_m = 0;
};
BoxCrossing CrossBox(const Box& box, const Vec3& a, const Vec3& b);

class Channel {
 public:
  Channel(double reference_loss_db, double exponent, bool shadowing, double db_per_wall,
          double db_per_m);

  int AddStation(const Vec3& position_m);  // Returns its index.
  void SetPosition(int station, const Vec3& position_m);
  const Vec3& position(int station) const { return positions_[station]; }
  void AddObstacle(const Box& box);
  int obstacle_count() const { return static_cast<int>(boxes_.size()); }

  // Total loss a <-> b in dB (symmetric), recomputing stale pairs first.
  double LossDb(int a, int b) {
    if (any_dirty_) Refresh();
    return loss_db_[static_cast<size_t>(a) * stride_ + b];
  }
  // 10^(-LossDb/10): received power = transmitted power * gain (cached too).
  double GainLinear(int a, int b) {
    if (any_dirty_) Refresh();
    return gain_[static_cast<size_t>(a) * stride_ + b];
  }
  // Uncached: log-distance loss for `distance_m` (the reference loss below 1 m, as ns-3).
  double PathLossDb(double distance_m) const;
  // Uncached: shadowing loss of the segment a -> b.
  double ShadowingDb(const Vec3& a, const Vec3& b);

 private:
  void Refresh();
  void RebuildGrid();
  double ComputeLoss(int a, int b);

  double reference_loss_db_, exponent_;
  bool shadowing_;
  double db_per_wall_, db_per_m_;
  std::vector<Vec3> positions_;
  std::vector<char> dirty_;
  bool any_dirty_ = false;
  size_t stride_ = 0;
  std::vector<double> loss_db_;  // stride_ x stride_, row-major.
  std::vector<double> gain_;     // Same layout, linear.

  // Obstacles and their grid.
  std::vector<Box> boxes_;
  bool grid_stale_ = true;
  double grid_x0_ = 0, grid_y0_ = 0, cell_m_ = 1;
  int grid_nx_ = 0, grid_ny_ = 0;
  std::vector<std::vector<int>> cells_;  // Box indices per cell.
  std::vector<uint32_t> visit_stamp_;    // Per box: last query that tested it.
  uint32_t stamp_ = 0;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_CHANNEL_H_

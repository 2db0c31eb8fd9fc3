// Obstacle culling (docs/physics.md, "Obstacle culling"): square tiles in x/y, each with the
// obstacles that a robot inside the tile (grown by a switching hysteresis) can touch or see
// with its lidar. World gives every robot the model of its tile, so a step costs the nearby
// obstacles only, with the same trajectory and ranges as the model holding them all.
#ifndef SITLNET_PHYSICS_MUJOCO_OBSTACLE_TILES_H_
#define SITLNET_PHYSICS_MUJOCO_OBSTACLE_TILES_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "scenario/scenario.h"

namespace sitlnet::physics {

// Tile (ix, iy) covers [ix * size, (ix + 1) * size) x [iy * size, (iy + 1) * size).
struct TileIndex {
  int64_t ix = 0, iy = 0;
  auto operator<=>(const TileIndex&) const = default;
};

// Axis-aligned rectangle in x/y (metres).
struct Rect {
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  // False for NaN coordinates.
  bool Contains(double x, double y) const {
    return x >= x_min && x <= x_max && y >= y_min && y <= y_max;
  }
};

class ObstacleTiles {
 public:
  // `tile_m` > 0. `reach_m`: how far from its centre a robot can touch or see anything during
  // one step (largest lidar max range, or body radius plus one step's travel, whichever is
  // larger); obstacles within hysteresis + reach of a tile go into its model.
  ObstacleTiles(const Scenario& scenario, double tile_m, double reach_m);

  // False when (x, y) is not finite or so far out that tile indices could overflow: such a
  // robot uses the model with every obstacle.
  bool HasTile(double x, double y) const;
  // The tile holding (x, y); requires HasTile(x, y).
  TileIndex TileOf(double x, double y) const;
  // Where a robot may be and keep tile `tile`'s model: the tile grown by the hysteresis, so a
  // robot hovering on a tile border does not switch models back and forth.
  Rect Region(TileIndex tile) const;
  // Indices into scenario.spec.obstacle() of every obstacle whose horizontal bounding box
  // (yaw included) intersects Region(tile) grown by the reach, in scenario order.
  std::vector<int> ObstaclesOf(TileIndex tile) const;
  // Every tile whose model holds at least one obstacle (ObstaclesOf not empty; every other tile
  // holds the ground alone), in index order; nullopt if the obstacles' surroundings cover more
  // than `max_tiles` tiles.
  std::optional<std::vector<TileIndex>> TilesNearObstacles(int64_t max_tiles) const;

  double tile_m() const { return tile_m_; }
  double hysteresis_m() const { return hysteresis_m_; }
  double margin_m() const { return margin_m_; }

 private:
  // Whether `box` reaches into the tile's area (the tile grown by the margin): the one test of
  // what a tile's model holds.
  bool Reaches(TileIndex tile, const Rect& box) const;

  double tile_m_;
  double hysteresis_m_;
  double margin_m_;           // hysteresis + reach + safety
  std::vector<Rect> bounds_;  // per obstacle: horizontal bounding box
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_OBSTACLE_TILES_H_

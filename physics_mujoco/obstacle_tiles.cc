#include "physics_mujoco/obstacle_tiles.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "common/common.h"

namespace sitlnet::physics {
namespace {

// Tile indices stay far from int64 overflow; a robot this far out (1e9 m) has diverged anyway.
constexpr double kMaxCoordinate_m = 1e9;
// Added to every model's margin so that rounding in the bounding boxes never matters.
constexpr double kSafety_m = 1.0;

}  // namespace

ObstacleTiles::ObstacleTiles(const Scenario& scenario, double tile_m, double reach_m)
    : tile_m_(tile_m), hysteresis_m_(tile_m / 8), margin_m_(tile_m / 8 + reach_m + kSafety_m) {
  SITLNET_DEMAND(tile_m > 0 && reach_m >= 0);
  for (const proto::Obstacle& box : scenario.spec.obstacle()) {
    // A box of half extents (hx, hy) turned by yaw spans |cos| hx + |sin| hy in x and
    // |sin| hx + |cos| hy in y.
    const double yaw_rad = box.yaw_deg() * std::numbers::pi / 180.0;
    const double c = std::abs(std::cos(yaw_rad)), s = std::abs(std::sin(yaw_rad));
    const double hx = box.size_m().x() / 2, hy = box.size_m().y() / 2;
    const double ex = c * hx + s * hy, ey = s * hx + c * hy;
    const double x = box.center_m().x(), y = box.center_m().y();
    bounds_.push_back({x - ex, x + ex, y - ey, y + ey});
  }
}

bool ObstacleTiles::HasTile(double x, double y) const {
  return std::abs(x) < kMaxCoordinate_m && std::abs(y) < kMaxCoordinate_m;  // false for NaN
}

TileIndex ObstacleTiles::TileOf(double x, double y) const {
  SITLNET_DEMAND(HasTile(x, y));
  return {static_cast<int64_t>(std::floor(x / tile_m_)),
          static_cast<int64_t>(std::floor(y / tile_m_))};
}

Rect ObstacleTiles::Region(TileIndex tile) const {
  const double x0 = static_cast<double>(tile.ix) * tile_m_;
  const double y0 = static_cast<double>(tile.iy) * tile_m_;
  return {x0 - hysteresis_m_, x0 + tile_m_ + hysteresis_m_, y0 - hysteresis_m_,
          y0 + tile_m_ + hysteresis_m_};
}

bool ObstacleTiles::Reaches(TileIndex tile, const Rect& box) const {
  const double x0 = static_cast<double>(tile.ix) * tile_m_;
  const double y0 = static_cast<double>(tile.iy) * tile_m_;
  return box.x_max >= x0 - margin_m_ && box.x_min <= x0 + tile_m_ + margin_m_ &&
         box.y_max >= y0 - margin_m_ && box.y_min <= y0 + tile_m_ + margin_m_;
}

std::vector<int> ObstacleTiles::ObstaclesOf(TileIndex tile) const {
  std::vector<int> inside;
  for (int i = 0; i < static_cast<int>(bounds_.size()); ++i) {
    if (Reaches(tile, bounds_[i])) inside.push_back(i);
  }
  return inside;
}

std::optional<std::vector<TileIndex>> ObstacleTiles::TilesNearObstacles(int64_t max_tiles) const {
  const auto index = [&](double v) {
    return static_cast<int64_t>(
        std::floor(std::clamp(v, -kMaxCoordinate_m, kMaxCoordinate_m) / tile_m_));
  };
  // Per obstacle, the tiles whose area (the tile grown by the margin, as in ObstaclesOf) reaches
  // its box: from the one whose far edge does (hence the -1) to the one whose near edge does
  // (+1: a quotient rounded just below a whole number); Reaches, ObstaclesOf's test, decides. Stops
  // as soon as there are too many.
  std::set<TileIndex> near;
  for (const Rect& b : bounds_) {
    for (int64_t ix = index(b.x_min - margin_m_) - 1; ix <= index(b.x_max + margin_m_) + 1; ++ix) {
      for (int64_t iy = index(b.y_min - margin_m_) - 1; iy <= index(b.y_max + margin_m_) + 1;
           ++iy) {
        if (!Reaches({ix, iy}, b)) continue;
        near.insert({ix, iy});
        if (static_cast<int64_t>(near.size()) > max_tiles) return std::nullopt;
      }
    }
  }
  return std::vector<TileIndex>(near.begin(), near.end());
}

}  // namespace sitlnet::physics

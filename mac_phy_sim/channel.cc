#include "mac_phy_sim/channel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mac_phy_sim/gamma.h"

namespace sitlnet::mac {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Parameter interval [t_in, t_out] of p + t d inside [lo, hi] on one axis.
bool Slab(double p, double d, double lo, double hi, double* t_in, double* t_out) {
  if (std::fabs(d) < 1e-15) return p >= lo && p <= hi;
  double t1 = (lo - p) / d, t2 = (hi - p) / d;
  if (t1 > t2) std::swap(t1, t2);
  *t_in = std::max(*t_in, t1);
  *t_out = std::min(*t_out, t2);
  return *t_in <= *t_out;
}

}  // namespace

PreparedBox PrepareBox(const Box& box) {
  PreparedBox p;
  p.center_m = box.center_m;
  p.half_m = Vec3d{box.size_m.x / 2, box.size_m.y / 2, box.size_m.z / 2};
  p.cos_yaw = std::cos(box.yaw_deg * kDegToRad);
  p.sin_yaw = std::sin(box.yaw_deg * kDegToRad);
  const double c = std::fabs(p.cos_yaw), s = std::fabs(p.sin_yaw);
  const double hx = c * p.half_m.x + s * p.half_m.y, hy = s * p.half_m.x + c * p.half_m.y;
  p.min_x = box.center_m.x - hx;
  p.max_x = box.center_m.x + hx;
  p.min_y = box.center_m.y - hy;
  p.max_y = box.center_m.y + hy;
  return p;
}

namespace {

// The part of a -> b inside `box`, as segment parameters enter < leave in [0, 1], and the
// segment's vector in the box frame; false when the segment misses the box.
struct BoxSpan {
  double t_in, t_out, enter, leave;
  Vec3d d;
};
[[gnu::always_inline]] inline bool SpanInBox(const PreparedBox& box, const Vec3d& a,
                                             const Vec3d& b, BoxSpan* span) {
  // Into the box frame: translate, then rotate by -yaw about z.
  const double c = box.cos_yaw, s = -box.sin_yaw;
  auto local = [&](const Vec3d& p) {
    const double x = p.x - box.center_m.x, y = p.y - box.center_m.y;
    return Vec3d{c * x - s * y, s * x + c * y, p.z - box.center_m.z};
  };
  const Vec3d la = local(a), lb = local(b);
  span->d = Vec3d{lb.x - la.x, lb.y - la.y, lb.z - la.z};
  const Vec3d& d = span->d;
  span->t_in = -std::numeric_limits<double>::infinity();
  span->t_out = std::numeric_limits<double>::infinity();
  const Vec3d& h = box.half_m;
  if (!Slab(la.x, d.x, -h.x, h.x, &span->t_in, &span->t_out) ||
      !Slab(la.y, d.y, -h.y, h.y, &span->t_in, &span->t_out) ||
      !Slab(la.z, d.z, -h.z, h.z, &span->t_in, &span->t_out)) {
    return false;
  }
  span->enter = std::max(span->t_in, 0.0);
  span->leave = std::min(span->t_out, 1.0);
  return !(span->enter >= span->leave);  // A not-a-number span goes on, as it always did.
}

// CrossPreparedBox(box, a, b).inside_m > 0 without the length's sqrt and the walls (3GPP's
// blocking test walks every link in full: this is its inner loop).
bool SegmentEntersBox(const PreparedBox& box, const Vec3d& a, const Vec3d& b) {
  BoxSpan span;
  if (!SpanInBox(box, a, b, &span)) return false;
  const Vec3d& d = span.d;
  return (span.leave - span.enter) * (d.x * d.x + d.y * d.y + d.z * d.z) > 0;
}

}  // namespace

BoxCrossing CrossPreparedBox(const PreparedBox& box, const Vec3d& a, const Vec3d& b) {
  BoxSpan span;
  if (!SpanInBox(box, a, b, &span)) return {};
  BoxCrossing crossing;
  crossing.walls = (span.t_in > 0 ? 1 : 0) + (span.t_out < 1 ? 1 : 0);
  const Vec3d& d = span.d;
  crossing.inside_m = (span.leave - span.enter) * std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return crossing;
}

BoxCrossing CrossBox(const Box& box, const Vec3d& a, const Vec3d& b) {
  return CrossPreparedBox(PrepareBox(box), a, b);
}

RadioChannel::RadioChannel(double reference_loss_db, double exponent, bool shadowing,
                           double db_per_wall, double db_per_m)
    : RadioChannel(std::make_unique<LogDistanceModel>(reference_loss_db, exponent), shadowing,
                   db_per_wall, db_per_m) {}

RadioChannel::RadioChannel(std::unique_ptr<PathLossModel> model, bool shadowing, double db_per_wall,
                           double db_per_m)
    : model_(std::move(model)),
      log_distance_(dynamic_cast<const LogDistanceModel*>(model_.get())),
      obstacle_shadowing_(shadowing && model_->ComposesWithObstacleShadowing()),
      obstacle_blockage_(shadowing && model_->UsesBlockage()),
      timed_(model_->ChangesWithTime()),
      shadowing_(shadowing),
      db_per_wall_(db_per_wall),
      db_per_m_(db_per_m) {}

int RadioChannel::AddStation(const Vec3d& position_m) {
  const int index = static_cast<int>(positions_.size());
  positions_.push_back(position_m);
  moved_epoch_.push_back(++epoch_);
  if (positions_.size() > stride_) {
    // Grow the matrices by doubling; everything is recomputed on demand.
    stride_ = std::max<size_t>(8, stride_ * 2);
    loss_db_.assign(stride_ * stride_, 0.0);
    gain_.assign(stride_ * stride_, 0.0);
    computed_epoch_.assign(stride_ * stride_, 0);
    if (timed_) recompute_after_ns_.assign(stride_ * stride_, kNeverNs);
    bound_db_.assign(stride_ * stride_, 0.0);
    bound_epoch_.assign(stride_ * stride_, 0);
  }
  return index;
}

void RadioChannel::SetPosition(int station, const Vec3d& position_m) {
  const Vec3d& old = positions_[station];
  if (old.x == position_m.x && old.y == position_m.y && old.z == position_m.z) return;
  positions_[station] = position_m;
  moved_epoch_[station] = ++epoch_;
}

void RadioChannel::AddObstacle(const Box& box) {
  boxes_.push_back(PrepareBox(box));
  visit_stamp_.push_back(0);
  grid_stale_ = true;
  obstacles_epoch_ = ++epoch_;
}

PathLossLink RadioChannel::Link(int a, int b) {
  PathLossLink link{a, b, positions_[a], positions_[b], false, clock_ns_ ? *clock_ns_ : 0};
  if (obstacle_blockage_) link.blocked = SegmentBlocked(link.a_m, link.b_m);
  return link;
}

double RadioChannel::PathLossDb(int a, int b) { return model_->LossDb(Link(a, b)); }

// Inlined into Recompute, as before there was a second caller: the path without fading is
// the hot one of most runs.
[[gnu::always_inline]] inline void RadioChannel::Store(int a, int b, double loss) {
  const double gain = std::pow(10.0, -loss / 10);
  for (const size_t index :
       {static_cast<size_t>(a) * stride_ + b, static_cast<size_t>(b) * stride_ + a}) {
    loss_db_[index] = loss;
    gain_[index] = gain;
    computed_epoch_[index] = epoch_;
  }
}

void RadioChannel::StoreExpiry(int a, int b) {
  const TimeNs after_ns = a == b ? kNeverNs : model_->RecomputeAfterNs(a, b);
  recompute_after_ns_[static_cast<size_t>(a) * stride_ + b] = after_ns;
  recompute_after_ns_[static_cast<size_t>(b) * stride_ + a] = after_ns;
}

void RadioChannel::Recompute(int a, int b) {
  Store(a, b, a == b ? 0.0 : ComputeLoss(a, b, dead_link_loss_db_, false));
  if (timed_) StoreExpiry(a, b);
}

double RadioChannel::RecomputeUntil(int a, int b, double stop_db) {
  const double loss = a == b ? 0.0 : ComputeLoss(a, b, stop_db, true);
  if (timed_) StoreExpiry(a, b);
  // Exact (the walk was not cut short): what Recompute would have stored.
  // Bounds go to their own cache, dead-for-everyone ones too (storing those
  // with their gain, a pow each, would cost more than it saves).
  if (loss < stop_db) {
    Store(a, b, loss);
    return loss;
  }
  for (const size_t index :
       {static_cast<size_t>(a) * stride_ + b, static_cast<size_t>(b) * stride_ + a}) {
    bound_db_[index] = loss;
    bound_epoch_[index] = epoch_;
  }
  return loss;
}

double RadioChannel::LognormalDb(int a, int b) const {
  if (lognormal_sigma_db_ <= 0) return 0;
  // Two uniforms from SplitMix64 (Steele et al. 2014) of the seed and the
  // unordered pair, then Box-Muller.
  const uint64_t pair = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  const uint64_t h1 = SplitMix64(lognormal_seed_ ^ SplitMix64(pair));
  const uint64_t h2 = SplitMix64(h1);
  const double u1 = (static_cast<double>(h1 >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = static_cast<double>(h2 >> 11) * 0x1.0p-53;
  return lognormal_sigma_db_ * std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

double RadioChannel::ComputeLoss(int a, int b, double stop_db, bool exact_below_stop) {
  const Vec3d& pa = positions_[a];
  const Vec3d& pb = positions_[b];
  double path_db;
  if (log_distance_ != nullptr) {
    const double dx = pb.x - pa.x, dy = pb.y - pa.y, dz = pb.z - pa.z;
    path_db = log_distance_->LossAtDistanceDb(std::sqrt(dx * dx + dy * dy + dz * dz));
  } else {
    path_db = model_->LossDb(Link(a, b));
  }
  double loss = path_db + LognormalDb(a, b);
  // Shadowing only adds loss: a link already dead in free space stays dead.
  if (obstacle_shadowing_ && !boxes_.empty() && loss < stop_db) {
    const double stop_at_db = stop_db - loss;
    const double shadowing_db = ShadowingDb(pa, pb, stop_at_db);
    loss += shadowing_db;
    // A sum cut short is only a lower bound: keep it at or above the stop even
    // where rounding would put it an ulp under, for callers that take a value
    // below the stop as exact.
    if (exact_below_stop && shadowing_db >= stop_at_db) loss = std::max(loss, stop_db);
  }
  return loss;
}

void RadioChannel::RebuildGrid() {
  grid_stale_ = false;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  for (const PreparedBox& box : boxes_) {
    x0 = std::min(x0, box.min_x);
    x1 = std::max(x1, box.max_x);
    y0 = std::min(y0, box.min_y);
    y1 = std::max(y1, box.max_y);
  }
  // About four cells per box over the covered area, at most 256 per axis.
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-6);
  cell_m_ = std::max(std::sqrt(area / (4.0 * boxes_.size())), 1e-3);
  cell_m_ = std::max({cell_m_, (x1 - x0) / 256, (y1 - y0) / 256});
  grid_x0_ = x0;
  grid_y0_ = y0;
  grid_nx_ = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell_m_)));
  grid_ny_ = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell_m_)));
  cells_.assign(static_cast<size_t>(grid_nx_) * grid_ny_, {});
  auto cell_of = [&](double v, double origin, int count) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / cell_m_)), 0, count - 1);
  };
  for (int k = 0; k < static_cast<int>(boxes_.size()); ++k) {
    const PreparedBox& box = boxes_[k];
    for (int ix = cell_of(box.min_x, x0, grid_nx_); ix <= cell_of(box.max_x, x0, grid_nx_); ++ix) {
      for (int iy = cell_of(box.min_y, y0, grid_ny_); iy <= cell_of(box.max_y, y0, grid_ny_);
           ++iy) {
        cells_[static_cast<size_t>(iy) * grid_nx_ + ix].push_back(k);
      }
    }
  }
}

double RadioChannel::ShadowingDb(const Vec3d& a, const Vec3d& b, double stop_at_db) {
  double loss_db = 0;
  WalkBoxes(
      a, b,
      [&](const PreparedBox& box) {
        const BoxCrossing crossing = CrossPreparedBox(box, a, b);
        loss_db += db_per_wall_ * crossing.walls + db_per_m_ * crossing.inside_m;
      },
      [&] { return loss_db >= stop_at_db; });
  return loss_db;
}

bool RadioChannel::SegmentBlocked(const Vec3d& a, const Vec3d& b) {
  bool blocked = false;
  WalkBoxes(
      a, b,
      [&](const PreparedBox& box) {
        if (!blocked) blocked = SegmentEntersBox(box, a, b);
      },
      [&] { return blocked; });
  return blocked;
}

template <typename OnBox, typename Done>
void RadioChannel::WalkBoxes(const Vec3d& a, const Vec3d& b, OnBox on_box, Done done) {
  if (boxes_.empty()) return;
  if (grid_stale_) RebuildGrid();
  if (++stamp_ == 0) {  // Wrapped: reset stamps so none looks visited.
    std::fill(visit_stamp_.begin(), visit_stamp_.end(), 0);
    stamp_ = 1;
  }
  // Clip the xy projection of the segment to the grid rectangle.
  const double dx = b.x - a.x, dy = b.y - a.y;
  double t_in = 0, t_out = 1;
  const double gx1 = grid_x0_ + grid_nx_ * cell_m_, gy1 = grid_y0_ + grid_ny_ * cell_m_;
  if (!Slab(a.x, dx, grid_x0_, gx1, &t_in, &t_out) ||
      !Slab(a.y, dy, grid_y0_, gy1, &t_in, &t_out)) {
    return;
  }
  const double seg_min_x = std::min(a.x, b.x), seg_max_x = std::max(a.x, b.x);
  const double seg_min_y = std::min(a.y, b.y), seg_max_y = std::max(a.y, b.y);
  auto visit = [&](int ix, int iy) {
    for (int k : cells_[static_cast<size_t>(iy) * grid_nx_ + ix]) {
      if (visit_stamp_[k] == stamp_) continue;
      visit_stamp_[k] = stamp_;
      const PreparedBox& box = boxes_[k];
      if (box.max_x < seg_min_x || box.min_x > seg_max_x || box.max_y < seg_min_y ||
          box.min_y > seg_max_y) {
        continue;  // Bounding rectangles apart: no crossing.
      }
      on_box(box);
    }
  };
  // Amanatides & Woo grid traversal from the entry point.
  const double px = a.x + t_in * dx, py = a.y + t_in * dy;
  int ix = std::clamp(static_cast<int>(std::floor((px - grid_x0_) / cell_m_)), 0, grid_nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((py - grid_y0_) / cell_m_)), 0, grid_ny_ - 1);
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double delta_x = std::fabs(dx) > 1e-15 ? cell_m_ / std::fabs(dx) : inf;
  const double delta_y = std::fabs(dy) > 1e-15 ? cell_m_ / std::fabs(dy) : inf;
  double next_x = inf, next_y = inf;
  if (std::fabs(dx) > 1e-15) {
    const double boundary = grid_x0_ + (ix + (dx > 0 ? 1 : 0)) * cell_m_;
    next_x = (boundary - a.x) / dx;
  }
  if (std::fabs(dy) > 1e-15) {
    const double boundary = grid_y0_ + (iy + (dy > 0 ? 1 : 0)) * cell_m_;
    next_y = (boundary - a.y) / dy;
  }
  while (true) {
    visit(ix, iy);
    if (done()) break;
    if (next_x <= next_y) {
      if (next_x > t_out) break;
      ix += step_x;
      next_x += delta_x;
    } else {
      if (next_y > t_out) break;
      iy += step_y;
      next_y += delta_y;
    }
    if (ix < 0 || iy < 0 || ix >= grid_nx_ || iy >= grid_ny_) break;
  }
}

}  // namespace sitlnet::mac

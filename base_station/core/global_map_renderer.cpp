#include "base_station/core/global_map_renderer.h"

#include <algorithm>
#include <cmath>

#include "common/laser_scan.h"

namespace cairn::base {

GlobalMapRenderer::GlobalMapRenderer(const OccupancyGridOptions& grid, const GlobalMapRenderOptions& options)
    : grid_options_(grid),
      options_(options),
      tile_m_(std::max(1.0, std::round(options.tile_m / grid.resolution_m)) * grid.resolution_m),
      grid_(grid) {}

GlobalMapRenderer::Tile GlobalMapRenderer::tile_of(const Eigen::Vector2d& p_m) const {
  return {int(std::floor(p_m.x() / tile_m_)), int(std::floor(p_m.y() / tile_m_))};
}

void GlobalMapRenderer::footprint(Drawn* d) const {
  // Beam ends as OccupancyGrid::insert_scan cuts them (max_range_m), plus the sensor origin.
  const double max_r = grid_options_.max_range_m;
  Eigen::Vector2d lo = d->T_global_base.translation(), hi = lo;
  auto extend = [&](const Eigen::Vector2f& p) {
    Eigen::Vector2d q = p.cast<double>();
    const double r = q.norm();
    if (r > max_r) q *= max_r / r;
    const Eigen::Vector2d w = d->T_global_base * q;
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  };
  for (const auto& p : d->hits) extend(p);
  for (const auto& p : d->no_return) extend(p);
  // A margin of one cell: a beam end on a tile border may land in the neighbouring cell.
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(grid_options_.resolution_m);
  d->lo_m = lo;
  d->hi_m = hi;
  d->lo = tile_of(lo - margin);
  d->hi = tile_of(hi + margin);
}

void GlobalMapRenderer::index(KeyframeId id, const Drawn& d, bool add) {
  for (int x = d.lo.first; x <= d.hi.first; ++x) {
    for (int y = d.lo.second; y <= d.hi.second; ++y) {
      if (add) {
        tiles_[{x, y}].insert(id);
      } else {
        auto it = tiles_.find({x, y});
        if (it == tiles_.end()) continue;
        it->second.erase(id);
        if (it->second.empty()) tiles_.erase(it);
      }
    }
  }
}

void GlobalMapRenderer::mark_dirty(const Drawn& d) {
  for (int x = d.lo.first; x <= d.hi.first; ++x) {
    for (int y = d.lo.second; y <= d.hi.second; ++y) dirty_.insert({x, y});
  }
}

void GlobalMapRenderer::set_pose(const Keyframe& kf, const SE2& T_global_base) {
  auto it = drawn_.find(kf.id);
  if (it != drawn_.end()) {
    const SE2 delta = it->second.T_global_base.between(T_global_base);
    if (delta.translation().norm() <= options_.min_move_m && std::abs(delta.yaw()) <= options_.min_turn_rad) return;
    mark_dirty(it->second);
    index(kf.id, it->second, false);
  } else {
    it = drawn_.emplace(kf.id, Drawn{}).first;
    Drawn& d = it->second;
    d.hits = scan_to_points(kf.scan);
    const float clear_m = float(std::min<double>(kf.scan.range_max_m, options_.no_return_clear_range_m));
    for (size_t i = 0; i < kf.scan.ranges_m.size(); ++i) {
      const float r = kf.scan.ranges_m[i];
      if (std::isnan(r) || r < kf.scan.range_max_m) continue;  // +inf and >= max: no return
      const float a = beam_angle_rad(kf.scan, i);
      d.no_return.emplace_back(clear_m * std::cos(a), clear_m * std::sin(a));
    }
  }
  Drawn& d = it->second;
  const bool is_new = d.lo_m.hasNaN();
  d.T_global_base = T_global_base;
  footprint(&d);
  index(kf.id, d, true);
  if (is_new) {
    appended_.push_back(kf.id);  // drawn on top unless a tile under it is re-rendered anyway
  } else {
    mark_dirty(d);
  }
}

void GlobalMapRenderer::remove(KeyframeId id) {
  auto it = drawn_.find(id);
  if (it == drawn_.end()) return;
  mark_dirty(it->second);
  index(id, it->second, false);
  drawn_.erase(it);
}

void GlobalMapRenderer::grow_for(const Eigen::Vector2d& lo_m, const Eigen::Vector2d& hi_m) {
  if (grid_.width() == 0) {
    grid_.reserve(lo_m, hi_m);
    return;
  }
  const Eigen::Vector2d grid_lo = grid_.origin_m();
  const Eigen::Vector2d grid_hi = grid_lo + grid_.resolution_m() * Eigen::Vector2d(grid_.width(), grid_.height());
  // Growing copies the whole grid: each side that grows does so by a quarter of the grid's size at
  // least, so growth stays amortised O(1) per cell.
  const Eigen::Vector2d margin = (0.25 * (grid_hi - grid_lo)).cwiseMax(Eigen::Vector2d::Constant(tile_m_));
  Eigen::Vector2d lo = grid_lo, hi = grid_hi - Eigen::Vector2d::Constant(grid_.resolution_m());
  bool grow = false;
  for (int i = 0; i < 2; ++i) {
    if (lo_m[i] < grid_lo[i]) lo[i] = std::min(lo_m[i], grid_lo[i] - margin[i]), grow = true;
    if (hi_m[i] >= grid_hi[i]) hi[i] = std::max(hi_m[i], grid_hi[i] + margin[i]), grow = true;
  }
  if (grow) grid_.reserve(lo, hi);
}

const OccupancyGrid& GlobalMapRenderer::render() {
  stats_ = GlobalMapRenderStats{};
  std::vector<const Drawn*> on_top;
  for (KeyframeId id : appended_) {
    auto it = drawn_.find(id);
    if (it == drawn_.end()) continue;  // removed meanwhile
    bool clean = true;
    for (int x = it->second.lo.first; x <= it->second.hi.first && clean; ++x) {
      for (int y = it->second.lo.second; y <= it->second.hi.second && clean; ++y) clean = !dirty_.count({x, y});
    }
    if (clean) {
      on_top.push_back(&it->second);
    } else {
      mark_dirty(it->second);  // drawn with its tiles' re-render
    }
  }
  appended_.clear();
  for (const Drawn* d : on_top) grow_for(d->lo_m, d->hi_m);
  for (const Drawn* d : on_top) grid_.insert_scan(d->T_global_base, d->hits, d->no_return);
  stats_.keyframes_drawn = int(on_top.size());
  if (dirty_.empty()) return grid_;
  // Grow once to hold every footprint that will be drawn (growing copies the whole grid).
  Eigen::Vector2d lo_m = Eigen::Vector2d::Constant(INFINITY), hi_m = -lo_m;
  for (const Tile& t : dirty_) {
    auto members = tiles_.find(t);
    if (members == tiles_.end()) continue;
    for (KeyframeId id : members->second) {
      const Drawn& d = drawn_.at(id);
      lo_m = lo_m.cwiseMin(d.lo_m);
      hi_m = hi_m.cwiseMax(d.hi_m);
    }
  }
  if (lo_m.allFinite()) grow_for(lo_m, hi_m);
  for (const Tile& t : dirty_) {
    const Eigen::Vector2d lo(t.first * tile_m_, t.second * tile_m_);
    const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(tile_m_);
    grid_.clear_region(lo, hi);
    ++stats_.tiles;
    auto members = tiles_.find(t);
    if (members == tiles_.end()) continue;
    for (KeyframeId id : members->second) {  // id order, as a full render
      const Drawn& d = drawn_.at(id);
      grid_.insert_scan_clipped(d.T_global_base, d.hits, d.no_return, lo, hi);
      ++stats_.keyframes_drawn;
    }
  }
  dirty_.clear();
  return grid_;
}

}  // namespace cairn::base

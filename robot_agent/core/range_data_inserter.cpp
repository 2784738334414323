#include "robot_agent/core/range_data_inserter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cairn::agent {

std::vector<uint16_t> compute_update_table(float probability) {
  const double odds = probability / (1.0 - probability);
  std::vector<uint16_t> table(kMaxValue + 1);
  table[kUnknownValue] = uint16_t(probability_to_value(probability) + kUpdateMarker);
  for (int v = 1; v <= kMaxValue; ++v) {
    const double p = value_to_probability(uint16_t(v));
    const double o = odds * p / (1.0 - p);
    table[v] = uint16_t(probability_to_value(float(o / (1.0 + o))) + kUpdateMarker);
  }
  return table;
}

RangeDataInserter::RangeDataInserter(const RangeDataInserterOptions& options)
    : options_(options),
      hit_table_(compute_update_table(options.hit_probability)),
      miss_table_(compute_update_table(options.miss_probability)) {}

void RangeDataInserter::apply(size_t index, const std::vector<uint16_t>& table, ZeroedVector<uint16_t>* cells,
                              ZeroedVector<size_t>* touched) const {
  uint16_t& v = (*cells)[index];
  if (v >= kUpdateMarker) return;  // already updated by this scan
  v = table[v];
  touched->push_back(index);
}

void RangeDataInserter::splat_segments(const std::vector<Eigen::Vector2d>& ends, const std::vector<bool>& hit,
                                       ProbabilityGrid* grid) const {
  const double res = grid->resolution_m();
  const double max_gap2 = options_.field_line_max_gap_m * options_.field_line_max_gap_m;
  const size_t n = ends.size();
  auto near = [&](size_t a, size_t b) { return hit[a] && hit[b] && (ends[b] - ends[a]).squaredNorm() <= max_gap2; };
  // Whether hit c lies on the line through hits a, b (within the larger of the tolerances).
  auto on_line = [&](size_t a, size_t b, size_t c) {
    const Eigen::Vector2d d = ends[b] - ends[a], e = ends[c] - ends[a];
    const double distance_m = std::abs(d.x() * e.y() - d.y() * e.x()) / std::max(1e-9, d.norm());
    return distance_m <= std::max(options_.field_line_tolerance_m, options_.field_line_tolerance_ratio * d.norm());
  };
  for (size_t i = 1; i < n; ++i) {
    if (!near(i - 1, i)) continue;
    const Eigen::Vector2d d = ends[i] - ends[i - 1];
    const double gap2 = d.squaredNorm();
    if (gap2 <= 4.0 * res * res) continue;  // the two kernels already overlap
    if (options_.field_line_collinear) {
      const bool before = i >= 2 && near(i - 2, i - 1) && on_line(i - 1, i, i - 2);
      const bool after = i + 1 < n && near(i, i + 1) && on_line(i - 1, i, i + 1);
      if (!before && !after) continue;
    }
    const int steps = int(std::ceil(std::sqrt(gap2) / res));
    for (int k = 1; k < steps; ++k) {
      const Eigen::Vector2i c = grid->cell_of(ends[i - 1] + d * (double(k) / steps));
      grid->splat_hit(c.x(), c.y(), options_.field_sigma_cells);
    }
  }
}

void RangeDataInserter::insert(const SE2& T, const std::vector<Eigen::Vector2f>& points, ProbabilityGrid* grid) const {
  if (points.empty()) return;
  const Eigen::Vector2d origin = T.translation();
  std::vector<Eigen::Vector2d> ends;
  std::vector<bool> hit;
  ends.reserve(points.size());
  Eigen::Vector2d lo = origin, hi = origin;
  for (const auto& p : points) {
    const double r = p.norm();
    const bool cut = r > options_.max_ray_length_m;
    const Eigen::Vector2d q =
        cut ? Eigen::Vector2d(p.cast<double>() * (options_.max_ray_length_m / r)) : Eigen::Vector2d(p.cast<double>());
    ends.push_back(T * q);
    hit.push_back(!cut);
    lo = lo.cwiseMin(ends.back());
    hi = hi.cwiseMax(ends.back());
  }
  const double pad = 2 * grid->resolution_m();
  grid->grow_to_include(lo - Eigen::Vector2d(pad, pad), hi + Eigen::Vector2d(pad, pad));
  grid->include_written_box(lo, hi);
  ZeroedVector<uint16_t>& cells = grid->mutable_values();
  const int w = grid->width();
  ZeroedVector<size_t>& touched = touched_;
  touched.clear();
  for (size_t i = 0; i < ends.size(); ++i) {
    if (!hit[i]) continue;
    const Eigen::Vector2i c = grid->cell_of(ends[i]);
    apply(size_t(c.y()) * w + c.x(), hit_table_, &cells, &touched);
    grid->splat_hit(c.x(), c.y(), options_.field_sigma_cells);
  }
  if (options_.field_line_max_gap_m > 0.0) splat_segments(ends, hit, grid);
  if (options_.insert_free_space) {
    const Eigen::Vector2i o = grid->cell_of(origin);
    const double free_m = options_.max_free_space_length_m;
    uint16_t* const v = cells.data();
    const uint16_t* const miss = miss_table_.data();
    for (const Eigen::Vector2d& end : ends) {
      // Bresenham from the sensor cell to (excluding) the endpoint cell.
      const double length_m = (end - origin).norm();
      const Eigen::Vector2d e =
          free_m > 0.0 && length_m > free_m ? Eigen::Vector2d(origin + (end - origin) * (free_m / length_m)) : end;
      const Eigen::Vector2i c = grid->cell_of(e);
      const int x = o.x(), y = o.y();
      const int dx = std::abs(c.x() - x), dy = -std::abs(c.y() - y);
      // The cells are inside the grid (grown to hold the origin and every end), so the linear index
      // identifies (x, y): stepping it replaces x += sx, y += sy and the row multiply.
      const ptrdiff_t step_x = x < c.x() ? 1 : -1, step_y = y < c.y() ? ptrdiff_t(w) : -ptrdiff_t(w);
      const size_t last = size_t(c.y()) * w + c.x();
      size_t index = size_t(y) * w + x;
      int err = dx + dy;
      // apply() without branches on the cell: every visited index is written to `touched`, which
      // keeps it only when the cell had not been updated by this scan yet (at most dx - dy cells).
      size_t count = touched.size();
      touched.resize(count + size_t(dx - dy) + 1);
      size_t* const t = touched.data();
      while (index != last) {
        const uint16_t old = v[index];
        const bool fresh = old < kUpdateMarker;
        v[index] = fresh ? miss[old & kMaxValue] : old;
        t[count] = index;
        count += fresh;
        const int e2 = 2 * err;
        if (e2 >= dy) {
          err += dy;
          index += step_x;
        }
        if (e2 <= dx) {
          err += dx;
          index += step_y;
        }
      }
      touched.resize(count);
    }
  }
  for (size_t index : touched) cells[index] -= kUpdateMarker;
}

}  // namespace cairn::agent

#include "robot_agent/core/correlative_scan_matcher.h"

#include <algorithm>
#include <cmath>

namespace cairn::agent {
namespace {

double max_range_m(const std::vector<Eigen::Vector2f>& points) {
  double r = 0.0;
  for (const auto& p : points) r = std::max(r, double(p.norm()));
  return r;
}

// Adds, for every translation offset (dx, dy) in [-n, n]^2, the probability at cell + offset of each
// point to scores[(dy + n) * side + dx + n]. Rows are read contiguously; out-of-grid reads `outside`.
void accumulate(const std::vector<Eigen::Vector2i>& cells, int n, const ProbabilityGrid& grid,
                std::vector<float>* scores) {
  const int side = 2 * n + 1;
  const std::vector<uint8_t>& values = grid.field();
  const int w = grid.width(), h = grid.height();
  for (const auto& c : cells) {
    const bool inside = c.x() - n >= 0 && c.y() - n >= 0 && c.x() + n < w && c.y() + n < h;
    for (int dy = -n; dy <= n; ++dy) {
      float* out = &(*scores)[size_t(dy + n) * side];
      if (inside) {
        const uint8_t* row = &values[size_t(c.y() + dy) * w + (c.x() - n)];
        for (int k = 0; k < side; ++k) out[k] += float(row[k]);
      } else {
        for (int k = 0; k < side; ++k) {
          const int col = c.x() - n + k, row = c.y() + dy;
          if (grid.contains(col, row)) out[k] += float(values[size_t(row) * w + col]);
        }
      }
    }
  }
}

}  // namespace

CorrelativeScanMatcher::CorrelativeScanMatcher(const CorrelativeScanMatcherOptions& options)
    : options_(options) {}

double CorrelativeScanMatcher::angular_step_rad(double range_m, double resolution_m) {
  range_m = std::max(range_m, 2.0 * resolution_m);
  // Law of cosines: the chord of a step at range r equals one cell (Cartographer, Olson).
  return std::acos(1.0 - (resolution_m * resolution_m) / (2.0 * range_m * range_m));
}

CorrelativeMatch CorrelativeScanMatcher::match(const SE2& initial, const std::vector<Eigen::Vector2f>& points,
                                               const ProbabilityGrid& grid, double linear_window_m,
                                               double angular_window_rad) const {
  CorrelativeMatch best;
  best.pose = initial;
  if (points.empty() || grid.width() == 0) return best;
  const double res = grid.resolution_m();
  const double range_m = std::min(max_range_m(points), options_.max_range_for_step_m);
  const double step_rad = angular_step_rad(range_m, res);
  const int num_angles = int(std::ceil(angular_window_rad / step_rad));
  const int n = int(std::ceil(linear_window_m / res));
  const int side = 2 * n + 1;
  std::vector<Eigen::Vector2i> cells(points.size());
  std::vector<float> scores(size_t(side) * side);
  double best_weighted = -1.0;
  for (int a = -num_angles; a <= num_angles; ++a) {
    const double dyaw = a * step_rad;
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(initial.yaw() + dyaw).toRotationMatrix();
    for (size_t i = 0; i < points.size(); ++i) {
      cells[i] = grid.cell_of(R * points[i].cast<double>() + initial.translation());
    }
    std::fill(scores.begin(), scores.end(), 0.f);
    accumulate(cells, n, grid, &scores);
    const double rot_cost = options_.rotation_delta_cost_weight * dyaw;
    for (int dy = -n; dy <= n; ++dy) {
      for (int dx = -n; dx <= n; ++dx) {
        const double raw = scores[size_t(dy + n) * side + dx + n] / (255.0 * double(points.size()));
        const double trans_cost = options_.translation_delta_cost_weight * res * std::hypot(double(dx), double(dy));
        const double weighted = raw * std::exp(-trans_cost * trans_cost - rot_cost * rot_cost);
        ++best.candidates;
        if (weighted > best_weighted) {
          best_weighted = weighted;
          best.score = raw;
          best.pose = SE2(initial.translation() + res * Eigen::Vector2d(dx, dy), initial.yaw() + dyaw);
        }
      }
    }
  }
  return best;
}

}  // namespace cairn::agent

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

// Cell indices of the points rotated by `yaw_rad` and placed at `t_m` (no translation offset yet).
void discretize(const std::vector<Eigen::Vector2f>& points, double yaw_rad, const Eigen::Vector2d& t_m,
                const ProbabilityGrid& grid, std::vector<Eigen::Vector2i>* cells) {
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(yaw_rad).toRotationMatrix();
  cells->clear();
  for (const auto& p : points) cells->push_back(grid.cell_of(R * p.cast<double>() + t_m));
}

double score_at(const std::vector<Eigen::Vector2i>& cells, int dx, int dy, const ProbabilityGrid& grid) {
  double sum = 0.0;
  const float outside = grid.fill_probability();
  for (const auto& c : cells) sum += grid.at(c.x() + dx, c.y() + dy, outside);
  return sum / double(cells.size());
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
                                               const ProbabilityGrid& likelihood) const {
  CorrelativeMatch best;
  best.pose = initial;
  if (points.empty() || likelihood.width() == 0) return best;
  const double res = likelihood.resolution_m();
  const double range_m = std::min(max_range_m(points), options_.max_range_for_step_m);
  const double step_rad = angular_step_rad(range_m, res);
  const int num_angles = int(std::ceil(options_.angular_window_rad / step_rad));
  const int num_linear = int(std::ceil(options_.linear_window_m / res));
  std::vector<Eigen::Vector2i> cells;
  cells.reserve(points.size());
  double best_weighted = -1.0;
  for (int a = -num_angles; a <= num_angles; ++a) {
    const double dyaw = a * step_rad;
    discretize(points, initial.yaw() + dyaw, initial.translation(), likelihood, &cells);
    const double rot_cost = options_.rotation_delta_cost_weight * dyaw;
    for (int dy = -num_linear; dy <= num_linear; ++dy) {
      for (int dx = -num_linear; dx <= num_linear; ++dx) {
        const double raw = score_at(cells, dx, dy, likelihood);
        const double dist_m = res * std::hypot(double(dx), double(dy));
        const double trans_cost = options_.translation_delta_cost_weight * dist_m;
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

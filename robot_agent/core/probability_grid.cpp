#include "robot_agent/core/probability_grid.h"

#include <algorithm>
#include <cmath>

namespace cairn::agent {

ProbabilityGrid::ProbabilityGrid(const Eigen::Vector2d& origin_m, double resolution_m, int width,
                                 int height, float fill_probability)
    : origin_m_(origin_m),
      resolution_m_(resolution_m),
      width_(std::max(0, width)),
      height_(std::max(0, height)),
      fill_probability_(fill_probability),
      cells_(size_t(width_) * size_t(height_), fill_probability) {}

ProbabilityGrid ProbabilityGrid::from_occupancy(const OccupancyGrid& grid, float unknown_probability) {
  ProbabilityGrid out(grid.origin_m(), grid.resolution_m(), grid.width(), grid.height(),
                      unknown_probability);
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) {
      const float l = grid.log_odds(c, r);
      if (l == 0.f) continue;
      out.mutable_at(c, r) = 1.f - 1.f / (1.f + std::exp(l));
    }
  }
  return out;
}

Eigen::Vector2i ProbabilityGrid::cell_of(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d c = (p_m - origin_m_) / resolution_m_;
  return {int(std::floor(c.x())), int(std::floor(c.y()))};
}

ProbabilityGrid ProbabilityGrid::blurred(double sigma_cells) const {
  if (sigma_cells <= 0.0 || cells_.empty()) return *this;
  const int radius = std::max(1, int(std::ceil(2.0 * sigma_cells)));
  std::vector<float> kernel(2 * radius + 1);
  float sum = 0.f;
  for (int k = -radius; k <= radius; ++k) {
    kernel[k + radius] = float(std::exp(-0.5 * k * k / (sigma_cells * sigma_cells)));
    sum += kernel[k + radius];
  }
  for (float& k : kernel) k /= sum;
  // Separable convolution; outside cells count as the fill probability.
  ProbabilityGrid tmp = *this, out = *this;
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * at(c + k, r, fill_probability_);
      tmp.mutable_at(c, r) = acc;
    }
  }
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * tmp.at(c, r + k, fill_probability_);
      out.mutable_at(c, r) = acc;
    }
  }
  return out;
}

}  // namespace cairn::agent

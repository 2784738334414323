#pragma once
// A dense, fixed-size snapshot of occupancy probabilities used for scan matching (Cartographer's
// ProbabilityGrid idea): built from a cairn::OccupancyGrid, unknown cells get a low prior so scan
// points falling into unexplored space are not rewarded. Rows grow with +y, columns with +x; cell
// (0,0) has its lower-left corner at origin_m(), like OccupancyGrid.
#include <Eigen/Core>
#include <vector>

#include "common/occupancy_grid.h"

namespace cairn::agent {

class ProbabilityGrid {
 public:
  ProbabilityGrid() = default;
  ProbabilityGrid(const Eigen::Vector2d& origin_m, double resolution_m, int width, int height,
                  float fill_probability);

  /// Probabilities of `grid`; unknown cells get `unknown_probability`.
  static ProbabilityGrid from_occupancy(const OccupancyGrid& grid, float unknown_probability);

  /// The grid convolved with a separable Gaussian of `sigma_cells` (kernel radius 2 sigma), used as
  /// the smooth likelihood field of the correlative search (Olson 2009, Sec. III).
  ProbabilityGrid blurred(double sigma_cells) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  bool contains(int col, int row) const { return col >= 0 && row >= 0 && col < width_ && row < height_; }
  /// Value of a cell; `outside` for cells out of bounds.
  float at(int col, int row, float outside) const {
    return contains(col, row) ? cells_[size_t(row) * width_ + col] : outside;
  }
  float& mutable_at(int col, int row) { return cells_[size_t(row) * width_ + col]; }
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p_m) const;
  /// Continuous cell coordinates (col, row) where integer values are cell centres.
  Eigen::Vector2d continuous_cell(const Eigen::Vector2d& p_m) const {
    return (p_m - origin_m_) / resolution_m_ - Eigen::Vector2d(0.5, 0.5);
  }
  float fill_probability() const { return fill_probability_; }

 private:
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  double resolution_m_ = 0.05;
  int width_ = 0;
  int height_ = 0;
  float fill_probability_ = 0.1f;
  std::vector<float> cells_;
};

}  // namespace cairn::agent

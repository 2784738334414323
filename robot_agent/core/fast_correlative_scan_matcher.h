#pragma once
// Branch-and-bound scan matching against a finished submap (Cartographer's
// FastCorrelativeScanMatcher2D; Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016,
// Sec. V): a stack of precomputation grids over the submap's likelihood field (probability_grid.h),
// level h holding for each cell the maximum field value
// over the 2^h x 2^h block starting there, bounds the score of every translation in such a block.
// Candidates are explored depth-first, best first, and a subtree is pruned as soon as its bound
// falls below the best score found, so a window of several metres and tens of degrees is searched
// exactly (at the grid resolution) in milliseconds.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "common/se2.h"
#include "robot_agent/core/probability_grid.h"

namespace cairn::agent {

struct FastCorrelativeScanMatcherOptions {
  int branch_and_bound_depth = 7;  ///< the coarsest level covers 2^(depth-1) cells
  double max_range_for_step_m = 15.0;
  /// Work cap: a search scoring more candidates than this gives up (returns no match), so an
  /// ambiguous place (loose bounds, nothing prunes) cannot stall the robot.
  int max_scored_candidates = 40000;
};

/// Level h of the stack: max over the 2^h x 2^h block with lower-left cell (col, row) of the
/// likelihood field (0..255).
class PrecomputationGrid {
 public:
  PrecomputationGrid() = default;
  /// From the grid itself (width 1), cropped to the cells whose field is non-zero, or from the
  /// previous level (block width = 2 * previous).
  static PrecomputationGrid from_grid(const ProbabilityGrid& grid);
  static PrecomputationGrid from_previous(const PrecomputationGrid& previous);
  uint8_t at(int col, int row) const {
    const unsigned c = unsigned(col - x0_), r = unsigned(row - y0_);
    return (c < unsigned(width_) && r < unsigned(height_)) ? cells_[size_t(r) * width_ + c] : 0;
  }
  int block_cells() const { return block_; }
  /// Sum of at(c + (dx, dy)) over `cells`.
  int sum(const std::vector<Eigen::Vector2i>& cells, int dx, int dy) const {
    int total = 0;
    const int ox = dx - x0_, oy = dy - y0_;
    const uint8_t* data = cells_.get();
    for (const auto& c : cells) {
      const unsigned col = unsigned(c.x() + ox), row = unsigned(c.y() + oy);
      if (col < unsigned(width_) && row < unsigned(height_)) total += data[size_t(row) * width_ + col];
    }
    return total;
  }
  /// sum() for cells whose bounding box [lo, hi] (before the offset) lies inside this level: no
  /// per-cell bounds check (the same total).
  bool contains_box(const Eigen::Vector2i& lo, const Eigen::Vector2i& hi, int dx, int dy) const {
    return lo.x() + dx >= x0_ && lo.y() + dy >= y0_ && hi.x() + dx < x0_ + width_ && hi.y() + dy < y0_ + height_;
  }
  int sum_inside(const std::vector<Eigen::Vector2i>& cells, int dx, int dy) const {
    int total = 0;
    const uint8_t* data = cells_.get() + (ptrdiff_t(dy - y0_) * width_ + (dx - x0_));
    for (const auto& c : cells) total += data[ptrdiff_t(c.y()) * width_ + c.x()];
    return total;
  }
  size_t bytes() const { return num_cells_; }

 private:
  int block_ = 1;
  int x0_ = 0, y0_ = 0;  ///< grid cell of the first column / row (blocks straddling the lower edge are kept)
  int width_ = 0, height_ = 0;
  std::unique_ptr<uint8_t[]> cells_;  ///< not value-initialised: every cell is written once
  size_t num_cells_ = 0;
  void allocate(int width, int height);
};

struct FastMatch {
  SE2 pose;            ///< T_grid_base
  double score = 0.0;  ///< mean likelihood field at the points, 0..1
};

class FastCorrelativeScanMatcher {
 public:
  FastCorrelativeScanMatcher(const ProbabilityGrid& grid, const FastCorrelativeScanMatcherOptions& options = {});

  /// Best pose within +-linear_window_m / +-angular_window_rad of `initial_T_grid_base` whose score
  /// is at least `min_score`; nullopt when none reaches it.
  std::optional<FastMatch> match(const SE2& initial_T_grid_base, const std::vector<Eigen::Vector2f>& points_base,
                                 double linear_window_m, double angular_window_rad, double min_score,
                                 int* scored_candidates = nullptr) const;
  /// Bytes of the precomputation levels built so far (they are built as searches need them).
  size_t memory_bytes() const;

 private:
  struct Candidate {
    int angle = 0, dx = 0, dy = 0;
    int score = 0;
  };
  /// The scan's points at one search angle, as grid cells, with their bounding box.
  struct DiscreteScan {
    std::vector<Eigen::Vector2i> cells;
    Eigen::Vector2i lo{0, 0}, hi{-1, -1};
  };
  int score(const DiscreteScan& scan, int level, int dx, int dy) const;
  /// Scores and sorts candidates[0, num_candidates) in place, then descends into the promising ones.
  std::optional<Candidate> search(const std::vector<DiscreteScan>& scans, Candidate* candidates, size_t num_candidates,
                                  int level, int max_offset, int min_score, int* budget) const;

  FastCorrelativeScanMatcherOptions options_;
  Eigen::Vector2d origin_m_;
  double resolution_m_;
  /// Builds the precomputation levels up to count - 1 (each from the previous one) if missing.
  void ensure_levels(int count) const;
  /// Level h: max over 2^h blocks. Built lazily (small search windows never read the coarse levels,
  /// the largest ones), hence mutable: a matcher must not be used from several threads at once.
  mutable std::vector<PrecomputationGrid> levels_;
};

}  // namespace cairn::agent

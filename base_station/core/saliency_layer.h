#pragma once
// The saliency layer over the global map (the paper's saliency map superimposed on the metric map,
// seed §3.4): every linked keyframe's salient spots (Keyframe::salient, robot_agent/core/objects/
// saliency_projection.h) at the keyframe's global pose, the strongest per cell. A spot keeps its
// weight until a robot has passed within inspected_radius_m of it (it has then been seen closely:
// the object pipeline had its look); from then on its weight decays by e every decay_s of mission
// time. A spot within explained_radius_m of an object already on the map is left out: saliency is
// attention for what has not been identified yet, and an object found needs no second look. The
// exploration planner weights frontiers by it (ExplorationContext::saliency). Found victims raise
// their surroundings in the planner itself (ExplorationOptions::victim_weight), not here: they
// never decay. Pure: the mapper's data in, a grid out.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/time.h"

namespace cairn::base {

struct MapperData;

struct SaliencyLayerOptions {
  double cell_m = 0.25;
  double inspected_radius_m = 1.5;  ///< a robot this close has seen the spot closely
  double decay_s = 30.0;            ///< after that, the weight falls by e every decay_s
  double explained_radius_m = 1.5;  ///< spots this close to a found object are left out
};

class SaliencyLayer {
 public:
  SaliencyLayer() = default;
  /// An all-zero layer over the box [min_m, max_m].
  SaliencyLayer(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, double cell_m);

  bool empty() const { return width_ == 0; }
  int width() const { return width_; }
  int height() const { return height_; }
  double cell_m() const { return cell_m_; }
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  /// The cell's value (0 outside the layer).
  double at(const Eigen::Vector2d& p_m) const;
  /// The largest value within `radius_m` of `p_m` (cells whose centre is that close).
  double max_within(const Eigen::Vector2d& p_m, double radius_m) const;
  /// Keeps the larger of the cell's value and `weight`; points outside are ignored.
  void raise(const Eigen::Vector2d& p_m, double weight);
  /// Cells whose value is at least `threshold`.
  int cells_above(double threshold) const;
  /// Centre of cell (col, row) and its value, for drawing.
  Eigen::Vector2d centre_m(int col, int row) const;
  double value(int col, int row) const { return values_[index(col, row)]; }
  /// Row-major index of cell (col, row), for grids of the same geometry.
  size_t index(int col, int row) const { return size_t(row) * size_t(width_) + size_t(col); }
  /// The cell under p_m; false off the layer (or not finite).
  bool cell_of(const Eigen::Vector2d& p_m, int* col, int* row) const;
  /// Calls f(col, row) for every cell of the layer whose centre is within radius_m of p_m.
  template <typename F>
  void for_each_cell_within(const Eigen::Vector2d& p_m, double radius_m, F&& f) const {
    if (empty() || !p_m.allFinite()) return;
    const int reach = int(std::ceil(radius_m / cell_m_)) + 1;
    const Eigen::Vector2i c0 = unclamped_cell(p_m);
    for (int r = std::max(0, c0.y() - reach); r <= std::min(height_ - 1, c0.y() + reach); ++r) {
      for (int c = std::max(0, c0.x() - reach); c <= std::min(width_ - 1, c0.x() + reach); ++c) {
        if ((centre_m(c, r) - p_m).norm() <= radius_m) f(c, r);
      }
    }
  }

 private:
  Eigen::Vector2i unclamped_cell(const Eigen::Vector2d& p_m) const {
    return ((p_m - origin_m_) / cell_m_).array().floor().cast<int>();
  }

  Eigen::Vector2d origin_m_{0, 0};  ///< lower-left corner of cell (0, 0)
  double cell_m_ = 0.25;
  int width_ = 0, height_ = 0;
  std::vector<float> values_;  ///< row-major, 0..1
};

/// The layer for everything the mapper holds at mission time `now_ns`, leaving out spots near
/// `objects_m` (the found objects, global frame); see the file comment. Empty when no linked
/// keyframe carries a salient spot that is not explained.
SaliencyLayer build_saliency_layer(const MapperData& data, StampNs now_ns,
                                   const std::vector<Eigen::Vector2d>& objects_m = {},
                                   const SaliencyLayerOptions& options = {});

}  // namespace cairn::base

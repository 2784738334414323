#include "base_station/core/saliency_layer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base_station/core/mapper_data.h"
#include "common/check.h"

namespace cairn::base {

SaliencyLayer::SaliencyLayer(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, double cell_m)
    : origin_m_(min_m), cell_m_(cell_m) {
  CAIRN_CHECK(cell_m > 0.0 && (max_m.array() >= min_m.array()).all(), "saliency layer: empty box or cell size");
  width_ = int(std::floor((max_m.x() - min_m.x()) / cell_m)) + 1;
  height_ = int(std::floor((max_m.y() - min_m.y()) / cell_m)) + 1;
  values_.assign(size_t(width_) * size_t(height_), 0.f);
}

bool SaliencyLayer::cell_of(const Eigen::Vector2d& p_m, int* col, int* row) const {
  if (empty() || !p_m.allFinite()) return false;
  const Eigen::Vector2i cell = unclamped_cell(p_m);
  *col = cell.x(), *row = cell.y();
  return *col >= 0 && *row >= 0 && *col < width_ && *row < height_;
}

Eigen::Vector2d SaliencyLayer::centre_m(int col, int row) const {
  return origin_m_ + cell_m_ * Eigen::Vector2d(col + 0.5, row + 0.5);
}

double SaliencyLayer::at(const Eigen::Vector2d& p_m) const {
  int c = 0, r = 0;
  return cell_of(p_m, &c, &r) ? value(c, r) : 0.0;
}

double SaliencyLayer::max_within(const Eigen::Vector2d& p_m, double radius_m) const {
  double best = 0.0;
  for_each_cell_within(p_m, radius_m, [&](int c, int r) { best = std::max(best, value(c, r)); });
  return best;
}

void SaliencyLayer::raise(const Eigen::Vector2d& p_m, double weight) {
  int c = 0, r = 0;
  if (!cell_of(p_m, &c, &r)) return;
  float& v = values_[index(c, r)];
  v = std::max(v, float(std::clamp(weight, 0.0, 1.0)));
}

int SaliencyLayer::cells_above(double threshold) const {
  return int(std::count_if(values_.begin(), values_.end(), [&](float v) { return v >= threshold; }));
}

SaliencyLayer build_saliency_layer(const MapperData& data, StampNs now_ns,
                                   const std::vector<Eigen::Vector2d>& objects_m, const SaliencyLayerOptions& o) {
  struct Spot {
    Eigen::Vector2d p_m;
    double weight;
    StampNs seen_ns;
  };
  std::vector<Spot> spots;
  std::vector<std::pair<Eigen::Vector2d, StampNs>> visits;  // every placed keyframe: where and when
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& [id, kf] : data.keyframes) {
    const std::optional<SE2> pose = data.global_pose(id);
    if (!pose) continue;
    visits.emplace_back(pose->translation(), kf.stamp_ns);
    for (const SalientPoint& s : kf.salient) {
      const Eigen::Vector2d p = *pose * Eigen::Vector2d(s.x_m, s.y_m);
      const bool explained = std::any_of(objects_m.begin(), objects_m.end(), [&](const Eigen::Vector2d& object) {
        return (object - p).norm() <= o.explained_radius_m;
      });
      if (explained) continue;
      spots.push_back({p, s.weight, kf.stamp_ns});
      lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    }
  }
  if (spots.empty()) return {};
  // When each cell was first passed within inspected_radius_m (kept only over the spots' box).
  SaliencyLayer layer(lo, hi, o.cell_m);
  const StampNs never = std::numeric_limits<StampNs>::max();
  std::vector<StampNs> first_close(size_t(layer.width()) * size_t(layer.height()), never);
  for (const auto& [p, stamp] : visits) {
    layer.for_each_cell_within(p, o.inspected_radius_m, [&, stamp = stamp](int c, int r) {
      StampNs& t = first_close[layer.index(c, r)];
      t = std::min(t, stamp);
    });
  }
  for (const Spot& s : spots) {
    int c = 0, r = 0;
    if (!layer.cell_of(s.p_m, &c, &r)) continue;  // never: the layer spans the spots
    const StampNs close_ns = first_close[layer.index(c, r)];
    double weight = s.weight;
    if (close_ns != never) {
      const double since_s = ns_to_sec(now_ns - std::max(close_ns, s.seen_ns));
      weight *= std::exp(-std::max(0.0, since_s) / o.decay_s);
    }
    layer.raise(s.p_m, weight);
  }
  return layer;
}

}  // namespace cairn::base

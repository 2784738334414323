#include "robot_agent/core/objects/saliency_projection.h"

#include <algorithm>
#include <cmath>

namespace cairn::agent {
namespace {

std::pair<int, int> cell_of(double x_m, double y_m, double cell_m) {
  return {int(std::floor(x_m / cell_m)), int(std::floor(y_m / cell_m))};
}

/// Keeps the stronger point of a cell.
void pool(std::map<std::pair<int, int>, SalientPoint>* cells, const SalientPoint& p, double cell_m) {
  auto [it, fresh] = cells->try_emplace(cell_of(p.x_m, p.y_m, cell_m), p);
  if (!fresh && p.weight > it->second.weight) it->second = p;
}

}  // namespace

std::vector<SalientPoint> project_saliency(const RgbdFrame& frame, const SaliencyMaps& maps,
                                           const SaliencyProjectionOptions& o) {
  if (maps.empty() || !frame.valid() || maps.colour.data.size() != maps.fused.data.size()) return {};
  const CameraIntrinsics& K = frame.intrinsics;
  const double su = double(K.width) / maps.width, sv = double(K.height) / maps.height;
  std::map<std::pair<int, int>, SalientPoint> cells;
  for (int r = 0; r < maps.height; ++r) {
    for (int c = 0; c < maps.width; ++c) {
      const double weight = maps.fused.at(r, c) * maps.colour.at(r, c);
      if (!(weight >= o.min_weight)) continue;
      // The cell's most colourful full-resolution pixel with a depth reading: a cell on the edge of
      // a colourful surface must take that surface's depth, not the wall's behind it.
      int u = -1, v = -1, best_chroma = -1;
      for (int y = int(r * sv); y < std::min(K.height, int((r + 1) * sv)); ++y) {
        for (int x = int(c * su); x < std::min(K.width, int((c + 1) * su)); ++x) {
          const size_t i = size_t(y) * size_t(K.width) + size_t(x);
          const uint8_t* px = &frame.rgb[3 * i];
          const int chroma = std::max({px[0], px[1], px[2]}) - std::min({px[0], px[1], px[2]});  // = 255 s v
          if (frame.depth[i] != 0 && chroma > best_chroma) best_chroma = chroma, u = x, v = y;
        }
      }
      if (u < 0) continue;
      const double z = frame.depth[size_t(v) * size_t(K.width) + size_t(u)] * K.depth_scale_m;
      if (!(z <= o.max_range_m)) continue;
      const Eigen::Vector3d p_camera((u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z);
      const Eigen::Vector3d p_base = frame.T_base_camera * p_camera;
      if (!p_base.allFinite() || p_base.z() < o.min_height_m || p_base.z() > o.max_height_m) continue;
      pool(&cells, SalientPoint{float(p_base.x()), float(p_base.y()), float(std::min(1.0, weight))}, o.cell_m);
    }
  }
  std::vector<SalientPoint> out;
  out.reserve(cells.size());
  for (const auto& [cell, p] : cells) out.push_back(p);
  return out;
}

void SaliencyPool::add(const SE2& T_local_base, const std::vector<SalientPoint>& points_base) {
  for (const SalientPoint& p : points_base) {
    const Eigen::Vector2d local = T_local_base * Eigen::Vector2d(p.x_m, p.y_m);
    pool(&cells_, SalientPoint{float(local.x()), float(local.y()), p.weight}, options_.cell_m);
  }
}

std::vector<SalientPoint> SaliencyPool::take(const SE2& T_local_keyframe) {
  const SE2 T_keyframe_local = T_local_keyframe.inverse();
  std::vector<SalientPoint> out;
  out.reserve(cells_.size());
  for (const auto& [cell, p] : cells_) {
    const Eigen::Vector2d q = T_keyframe_local * Eigen::Vector2d(p.x_m, p.y_m);
    out.push_back(SalientPoint{float(q.x()), float(q.y()), p.weight});
  }
  cells_.clear();
  std::stable_sort(out.begin(), out.end(),
                   [](const SalientPoint& a, const SalientPoint& b) { return a.weight > b.weight; });
  if (int(out.size()) > options_.max_points_per_keyframe) out.resize(size_t(options_.max_points_per_keyframe));
  return out;
}

}  // namespace cairn::agent

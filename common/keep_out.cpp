#include "common/keep_out.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace cairn {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

// Convex: p is inside when it lies on the same side of every edge (a handful of cross products;
// no geometry library is linked into common for it). Within a micrometre of an edge counts as on
// it: a point on a rectangle's edge, turned into another frame, lands a rounding error off it.
bool KeepOutPolygon::contains(const Eigen::Vector2d& p_m) const {
  constexpr double kOnEdge_m = 1e-6;
  bool left = false, right = false;
  for (size_t i = 0; i < corners_m.size(); ++i) {
    const Eigen::Vector2d& a = corners_m[i];
    const Eigen::Vector2d& b = corners_m[(i + 1) % corners_m.size()];
    const double side_m = cross(b - a, p_m - a) / std::max((b - a).norm(), kOnEdge_m);  // signed distance
    left |= side_m > kOnEdge_m;
    right |= side_m < -kOnEdge_m;
  }
  return !(left && right);
}

Eigen::Vector2d KeepOutPolygon::min_m() const {
  Eigen::Vector2d lo = corners_m[0];
  for (const auto& c : corners_m) lo = lo.cwiseMin(c);
  return lo;
}

Eigen::Vector2d KeepOutPolygon::max_m() const {
  Eigen::Vector2d hi = corners_m[0];
  for (const auto& c : corners_m) hi = hi.cwiseMax(c);
  return hi;
}

KeepOutPolygon in_frame(const KeepOutArea& area, const SE2& T_frame_map) {
  KeepOutPolygon p;
  p.id = area.id;
  p.corners_m = {T_frame_map * area.min_m, T_frame_map * Eigen::Vector2d(area.max_m.x(), area.min_m.y()),
                 T_frame_map * area.max_m, T_frame_map * Eigen::Vector2d(area.min_m.x(), area.max_m.y())};
  return p;
}

std::optional<std::string> polygon_fault(const KeepOutPolygon& polygon) {
  const std::string name = "keep-out area " + std::to_string(polygon.id);
  for (const auto& c : polygon.corners_m) {
    if (!c.allFinite()) return name + ": a corner is not a finite number";
  }
  double turn = 0, area2 = 0;
  for (size_t i = 0; i < polygon.corners_m.size(); ++i) {
    const Eigen::Vector2d& a = polygon.corners_m[i];
    const Eigen::Vector2d& b = polygon.corners_m[(i + 1) % 4];
    const Eigen::Vector2d& c = polygon.corners_m[(i + 2) % 4];
    const double z = cross(b - a, c - b);
    if (turn * z < 0) return name + ": its corners are not in convex order";
    if (z != 0) turn = z;
    area2 += cross(a, b);
  }
  if (std::abs(area2) < 1e-6) return name + ": its corners enclose no area";
  return std::nullopt;
}

// Each edge moves out by margin_m; a corner moves to where its two moved edges meet (the miter:
// along the sum of the edges' outward normals, scaled by 1 / (1 + cos of the angle between them)).
KeepOutPolygon grown(const KeepOutPolygon& p, double margin_m) {
  CAIRN_CHECK(margin_m >= 0 && !polygon_fault(p), "growing a bad keep-out polygon");
  const size_t n = p.corners_m.size();
  double twice_area = 0;
  for (size_t i = 0; i < n; ++i) twice_area += cross(p.corners_m[i], p.corners_m[(i + 1) % n]);
  const double outward = twice_area > 0 ? 1.0 : -1.0;  // counter-clockwise: the right-hand normal points out
  auto normal = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d d = (b - a).normalized();
    return Eigen::Vector2d(outward * d.y(), -outward * d.x());
  };
  KeepOutPolygon out = p;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& prev = p.corners_m[(i + n - 1) % n];
    const Eigen::Vector2d& here = p.corners_m[i];
    const Eigen::Vector2d& next = p.corners_m[(i + 1) % n];
    const Eigen::Vector2d n_in = normal(prev, here), n_out = normal(here, next);
    out.corners_m[i] = here + margin_m * (n_in + n_out) / (1.0 + n_in.dot(n_out));
  }
  return out;
}

std::vector<KeepOutPolygon> closed_around(const std::vector<KeepOutPolygon>& areas, const Eigen::Vector2d& p_m,
                                          double margin_m) {
  std::vector<KeepOutPolygon> closed;
  for (const KeepOutPolygon& a : areas) {
    if (a.contains(p_m)) continue;
    const KeepOutPolygon g = grown(a, margin_m);
    closed.push_back(g.contains(p_m) ? a : g);
  }
  return closed;
}

}  // namespace cairn

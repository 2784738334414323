#include "sim/floor_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn::sim {

FloorPlan::FloorPlan(int width, int height, double resolution_m, const Eigen::Vector2d& origin_m,
                     std::vector<uint8_t> walls)
    : width_(width), height_(height), resolution_m_(resolution_m), origin_m_(origin_m), walls_(std::move(walls)) {
  walls_.resize(size_t(std::max(0, width_)) * size_t(std::max(0, height_)), 0);
}

Eigen::Vector2i FloorPlan::cell_of(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d g = (p_m - origin_m_) / resolution_m_;
  return {int(std::floor(g.x())), int(std::floor(g.y()))};
}

bool FloorPlan::wall_at(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2i c = cell_of(p_m);
  return wall(c.x(), c.y());
}

RayHit FloorPlan::cast_ray(const Eigen::Vector2d& from_m, double angle_rad, double max_range_m) const {
  return cast_ray_dir(from_m, Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad)), max_range_m);
}

// Amanatides-Woo traversal in grid units. t is the distance along the ray in cells; a wall cell
// stops the ray at the face through which it was entered.
RayHit FloorPlan::cast_ray_dir(const Eigen::Vector2d& from_m, const Eigen::Vector2d& dir, double max_range_m) const {
  RayHit out;
  out.range_m = max_range_m;
  const double inv_res = 1.0 / resolution_m_;
  const double gx = (from_m.x() - origin_m_.x()) * inv_res;
  const double gy = (from_m.y() - origin_m_.y()) * inv_res;
  const double t_max_cells = max_range_m * inv_res;
  int cx = int(std::floor(gx)), cy = int(std::floor(gy));
  if (wall(cx, cy)) {
    out.hit = true;
    out.range_m = 0.0;
    out.col = cx;
    out.row = cy;
    return out;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int step_x = dir.x() > 0 ? 1 : -1;
  const int step_y = dir.y() > 0 ? 1 : -1;
  const double dt_x = dir.x() != 0 ? std::abs(1.0 / dir.x()) : kInf;
  const double dt_y = dir.y() != 0 ? std::abs(1.0 / dir.y()) : kInf;
  double t_x = dir.x() > 0 ? (cx + 1 - gx) * dt_x : (dir.x() < 0 ? (gx - cx) * dt_x : kInf);
  double t_y = dir.y() > 0 ? (cy + 1 - gy) * dt_y : (dir.y() < 0 ? (gy - cy) * dt_y : kInf);
  // Once the ray has left the map moving outward it can never come back.
  while (true) {
    double t;
    bool x_face;
    if (t_x < t_y) {
      t = t_x;
      x_face = true;
      cx += step_x;
      t_x += dt_x;
    } else {
      t = t_y;
      x_face = false;
      cy += step_y;
      t_y += dt_y;
    }
    if (t > t_max_cells) return out;
    if ((cx < 0 && step_x < 0) || (cx >= width_ && step_x > 0) || (cy < 0 && step_y < 0) ||
        (cy >= height_ && step_y > 0)) {
      return out;
    }
    if (wall(cx, cy)) {
      out.hit = true;
      out.range_m = t * resolution_m_;
      out.x_face = x_face;
      out.col = cx;
      out.row = cy;
      return out;
    }
  }
}

bool FloorPlan::disc_free(const Eigen::Vector2d& p_m, double radius_m) const {
  const Eigen::Vector2i lo = cell_of(p_m - Eigen::Vector2d::Constant(radius_m));
  const Eigen::Vector2i hi = cell_of(p_m + Eigen::Vector2d::Constant(radius_m));
  if (!contains(lo.x(), lo.y()) || !contains(hi.x(), hi.y())) return false;
  for (int r = lo.y(); r <= hi.y(); ++r) {
    for (int c = lo.x(); c <= hi.x(); ++c) {
      if (!wall(c, r)) continue;
      // Distance from p to the closest point of the cell square.
      const Eigen::Vector2d cmin = origin_m_ + resolution_m_ * Eigen::Vector2d(c, r);
      const Eigen::Vector2d cmax = cmin + Eigen::Vector2d::Constant(resolution_m_);
      const Eigen::Vector2d q = p_m.cwiseMax(cmin).cwiseMin(cmax);
      if ((q - p_m).norm() < radius_m) return false;
    }
  }
  return true;
}

bool FloorPlan::segment_free(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, double radius_m) const {
  // Discs every quarter cell along the segment: the swept area is covered up to 1/8 cell.
  const double len = (b_m - a_m).norm();
  const int n = std::max(1, int(std::ceil(len / (0.25 * resolution_m_))));
  for (int i = 0; i <= n; ++i) {
    if (!disc_free(a_m + (b_m - a_m) * (double(i) / n), radius_m)) return false;
  }
  return true;
}

}  // namespace cairn::sim

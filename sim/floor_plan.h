#pragma once
// The simulator's static map: a binary grid of wall cells built from a floor-plan image, with an
// exact grid ray caster (Amanatides & Woo, "A Fast Voxel Traversal Algorithm", 1987) used by the
// laser and the camera, and clearance checks used to validate robot routes.
// Grid convention as common/occupancy_grid.h: rows grow with +y, columns with +x, cell (0,0) has its
// lower-left corner at origin_m(). Cells outside the image are free for ray casting (no return) and
// blocked for clearance checks (robots must stay on the map).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cairn::sim {

/// Result of a 2D ray cast.
struct RayHit {
  bool hit = false;
  double range_m = 0.0;    ///< distance to the wall face along the ray (max range when !hit)
  bool x_face = false;     ///< the ray entered the wall cell through a face of constant x
  int col = -1, row = -1;  ///< the wall cell that was hit
};

class FloorPlan {
 public:
  FloorPlan() = default;
  /// `walls` is row-major, width*height, row 0 at the bottom (y = origin.y), non-zero = wall.
  FloorPlan(int width, int height, double resolution_m, const Eigen::Vector2d& origin_m, std::vector<uint8_t> walls);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  /// World coordinates of the upper-right corner of the map.
  Eigen::Vector2d max_m() const { return origin_m_ + resolution_m_ * Eigen::Vector2d(width_, height_); }

  bool contains(int col, int row) const { return col >= 0 && row >= 0 && col < width_ && row < height_; }
  /// True for wall cells; false outside the map.
  bool wall(int col, int row) const {
    return contains(col, row) && walls_[size_t(row) * size_t(width_) + size_t(col)] != 0;
  }
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p_m) const;
  /// True when p is on the map and its cell is a wall.
  bool wall_at(const Eigen::Vector2d& p_m) const;

  /// Casts a ray from `from_m` along the unit direction (cos, sin of `angle_rad`) up to max_range_m.
  RayHit cast_ray(const Eigen::Vector2d& from_m, double angle_rad, double max_range_m) const;
  RayHit cast_ray_dir(const Eigen::Vector2d& from_m, const Eigen::Vector2d& unit_dir, double max_range_m) const;

  /// True when every point within radius_m of p is on the map and not a wall.
  bool disc_free(const Eigen::Vector2d& p_m, double radius_m) const;
  /// True when the segment a-b swept by a disc of radius_m touches no wall and stays on the map.
  bool segment_free(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, double radius_m) const;

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  std::vector<uint8_t> walls_;
};

}  // namespace cairn::sim

#pragma once
// Object centre from its visible surface: the visible-surface centroid is biased toward the viewer
// (by ~pi/4 r for a cylinder), so fit the primitive the class cue suggests and take its centre.
// Sphere: algebraic least squares |p - c|^2 = r^2 (linear in c, r^2 - |c|^2). Vertical cylinder:
// circle fit (Kasa) on the ground-plane projection, height from the z extent. Box: minimum-area
// footprint rectangle over yaw (the top face is usually visible from a 0.5 m camera for low boxes),
// height from the z extent. best_shape_fit() keeps the primitive with the lowest RMS residual among
// plausible ones. Pure Eigen; points in a z-up frame (the robot's local map frame).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace cairn::agent {

enum class ShapeKind { kUnknown, kBox, kCylinder, kSphere };
const char* to_string(ShapeKind kind);

struct ShapeFit {
  ShapeKind kind = ShapeKind::kUnknown;
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;      ///< box only
  bool converged = false;
  double score = 0.0;        ///< RMS residual, m
  std::string reason;
};

struct ShapeFitOptions {
  double min_radius_m = 0.05;
  double max_radius_m = 0.8;
  double box_preference_m = 0.004;  ///< a curved fit must beat the box by this much RMS
  int min_points = 12;
};

ShapeFit fit_sphere(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
ShapeFit fit_vertical_cylinder(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
ShapeFit fit_box(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
/// Best of the three; `viewpoint_m` (the camera, same frame) rejects curved fits whose centre lies
/// in front of the surface.
ShapeFit best_shape_fit(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& viewpoint_m,
                        const ShapeFitOptions& options = {});

}  // namespace cairn::agent

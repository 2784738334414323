#pragma once
// Object centre from its visible surface: the visible-surface centroid is biased toward the viewer
// (by ~pi/4 r for a cylinder), so fit the primitive the class cue suggests and take its centre.
// Sphere: algebraic least squares |p - c|^2 = r^2 (linear in c, r^2 - |c|^2). Vertical cylinder:
// circle fit (Kasa) on the ground-plane projection, height from the z extent. Box: footprint
// rectangle over yaw by the L-shape closeness criterion (the top face is usually visible from a 0.5 m camera for low
// boxes), height from the z extent. best_shape_fit() keeps the primitive with the lowest RMS residual among plausible
// ones. Pure Eigen; points in a z-up frame (the robot's local map frame).
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
  double yaw_rad = 0.0;  ///< box only
  bool converged = false;
  double score = 0.0;  ///< RMS residual, m
  std::string reason;
};

struct ShapeFitOptions {
  double min_radius_m = 0.05;
  double max_radius_m = 0.8;
  double box_preference_m = 0.004;  ///< a curved fit must beat the box by this much RMS
  int min_points = 12;
  double top_face_band_m = 0.04;    ///< box yaw: points this close below the top are top-face points
  double closeness_floor_m = 0.01;  ///< box yaw: closeness criterion distance floor
  /// Known footprint of this class when box-shaped (long, short side; 0: unknown). A box is seen
  /// from one side: its far faces are hidden, so the footprint of the visible points is short along
  /// the viewing direction and its centre lies toward the camera (a lying victim seen broadside:
  /// half its 0.5 m width). complete_box_footprint() extends the hidden sides to this size.
  Eigen::Vector2d box_footprint_prior_m = Eigen::Vector2d::Zero();
  /// An axis is only extended when the viewing direction has at least this cosine along it (seen
  /// along a face, the missing part is not behind the visible one: it is cut off at either end).
  double min_completion_view_cos = 0.3;
  /// Only views whose points lie on the fitted rectangle's faces (RMS residual at most this) are
  /// completed: a partial footprint with points inside it is a curved surface, not a box.
  double max_completion_rms_m = 0.015;
  /// An axis is only extended when the other fitted side is within this fraction of its prior side
  /// (that side is seen whole, so the interpretation of the view is known).
  double completion_side_tolerance = 0.3;
};

ShapeFit fit_sphere(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
ShapeFit fit_vertical_cylinder(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
ShapeFit fit_box(const std::vector<Eigen::Vector3d>& points, const ShapeFitOptions& options = {});
/// Extends a box fit's footprint to options.box_footprint_prior_m on the sides hidden from
/// `viewpoint_m` (never shrinks it): the short prior side goes to the fitted side closest to it
/// unless a fitted side would then exceed its prior, then each short axis grows away from the
/// camera, moving the centre by half the missing extent. Only for views whose points lie on the
/// rectangle's faces (RMS <= max_completion_rms_m) and axes seen at an angle (min_completion_view_cos).
void complete_box_footprint(ShapeFit* fit, const Eigen::Vector3d& viewpoint_m, const ShapeFitOptions& options);

/// Best of the three (a box completed by complete_box_footprint when the class has a prior); `viewpoint_m` (the camera,
/// same frame) rejects curved fits whose centre lies in front of the surface.
ShapeFit best_shape_fit(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& viewpoint_m,
                        const ShapeFitOptions& options = {});

}  // namespace cairn::agent

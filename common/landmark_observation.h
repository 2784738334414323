#pragma once
// An identified landmark (a fiducial marker, "a red round mark" of the paper's Fig. 12e, a numbered
// sign) observed by range and bearing from a robot's base frame. The id is the landmark's identity
// in the world, shared by every robot: the same id seen by two robots (or twice by one) is the same
// physical thing, which the base station turns into constraints (base_station/core/landmarks.h).
#include <Eigen/Core>
#include <cmath>
#include <string>

#include "common/ids.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn {

/// Range and bearing of a landmark in a robot's base frame (x forward, y left; bearing CCW from x).
/// In a Keyframe the observation is expressed from that keyframe's base frame (the agent re-expresses
/// observations made between keyframes); stamp_ns keeps when it was actually seen.
struct LandmarkObservation {
  LandmarkId id;
  StampNs stamp_ns = 0;
  double range_m = 0.0;
  double bearing_rad = 0.0;
  double sigma_range_m = 0.05;
  double sigma_bearing_rad = 0.02;

  /// The observed point in the observing base frame.
  Eigen::Vector2d point_m() const { return {range_m * std::cos(bearing_rad), range_m * std::sin(bearing_rad)}; }
};

/// Why an observation is unusable (NaN or negative values, zero sigma, invalid id), empty if valid.
inline std::string validate_landmark_observation(const LandmarkObservation& o) {
  if (!o.id.valid()) return "invalid landmark id " + std::to_string(o.id.value);
  if (!std::isfinite(o.range_m) || o.range_m < 0.0) return "range_m must be finite and >= 0";
  if (!std::isfinite(o.bearing_rad)) return "bearing_rad must be finite";
  if (!std::isfinite(o.sigma_range_m) || o.sigma_range_m <= 0.0) return "sigma_range_m must be finite and > 0";
  if (!std::isfinite(o.sigma_bearing_rad) || o.sigma_bearing_rad <= 0.0) {
    return "sigma_bearing_rad must be finite and > 0";
  }
  return {};
}

/// Covariance of point_m() (first-order propagation of the range/bearing sigmas).
inline Eigen::Matrix2d landmark_point_covariance(const LandmarkObservation& o) {
  const double c = std::cos(o.bearing_rad), s = std::sin(o.bearing_rad);
  Eigen::Matrix2d J;
  J << c, -o.range_m * s, s, o.range_m * c;
  const Eigen::Vector2d var(o.sigma_range_m * o.sigma_range_m, o.sigma_bearing_rad * o.sigma_bearing_rad);
  return J * var.asDiagonal() * J.transpose();
}

/// The same observation expressed from another base frame `new` (T_new_old maps the observing frame
/// into it): the point moves exactly; the sigmas are the polar standard deviations of the moved point
/// covariance about the new origin (correlation dropped; the bearing sigma is floored at the
/// original's). Used by the agent to attach observations made between keyframes to a keyframe.
inline LandmarkObservation reexpress_landmark(const LandmarkObservation& o, const SE2& T_new_old) {
  const Eigen::Vector2d p = T_new_old * o.point_m();
  const Eigen::Matrix2d R = T_new_old.rotation();
  const Eigen::Matrix2d C = R * landmark_point_covariance(o) * R.transpose();
  LandmarkObservation out = o;
  out.range_m = p.norm();
  out.bearing_rad = std::atan2(p.y(), p.x());
  const double r = std::max(out.range_m, 1e-6);
  const Eigen::Vector2d u = p / r, v(-u.y(), u.x());  // radial and tangential directions
  out.sigma_range_m = std::sqrt(std::max(double(u.transpose() * C * u), 1e-12));
  out.sigma_bearing_rad = std::max(std::sqrt(std::max(double(v.transpose() * C * v), 0.0)) / r, o.sigma_bearing_rad);
  return out;
}

}  // namespace cairn

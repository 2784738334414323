#include "robot_agent/core/navigation/path_follower.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace cairn::agent {
namespace {

/// The point of segment [a, b] nearest p.
Eigen::Vector2d closest_on_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 <= 0.0) return a;
  return a + std::clamp((p - a).dot(d) / len2, 0.0, 1.0) * d;
}

/// Segments ahead of the current one that the projection may jump to in one update (the robot
/// moves a few centimetres per scan; a path doubling back on itself must not be short-cut).
constexpr size_t kProjectionWindow = 30;

/// The shortest lookahead tried when the arc to the usual one would touch a return.
constexpr double kMinLookaheadM = 0.15;

}  // namespace

double obstacle_ahead_m(const LaserScan& scan, double robot_radius_m, double half_width_m) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2f& p : scan_to_points(scan)) {
    if (p.x() > 0.f && std::abs(p.y()) <= half_width_m) nearest = std::min(nearest, double(p.x()) - robot_radius_m);
  }
  return nearest;
}

double free_travel_m(const LaserScan& scan, double robot_radius_m, double curvature_per_m, double max_m) {
  constexpr double kStepM = 0.02;
  const std::vector<Eigen::Vector2f> points = scan_to_points(scan);
  const double r2 = robot_radius_m * robot_radius_m;
  const double k = curvature_per_m;
  for (double s = 0; s <= max_m + 1e-9; s += kStepM) {
    // The disc's centre and heading after s metres on the arc from the origin, heading +x.
    const Eigen::Vector2d c = std::abs(k * s) < 1e-9 ? Eigen::Vector2d(s, 0)
                                                     : Eigen::Vector2d(std::sin(k * s) / k, (1 - std::cos(k * s)) / k);
    const Eigen::Vector2d heading(std::cos(k * s), std::sin(k * s));
    for (const Eigen::Vector2f& p : points) {
      const Eigen::Vector2d q = p.cast<double>() - c;
      // Inside the disc and in its front half: driving on would push into it (a return touching
      // its back half is being left behind).
      if (q.squaredNorm() < r2 && q.dot(heading) > 0) return s;
    }
  }
  return std::numeric_limits<double>::infinity();
}

double nearest_obstacle_m(const LaserScan& scan, double robot_radius_m) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2f& p : scan_to_points(scan)) nearest = std::min(nearest, double(p.norm()) - robot_radius_m);
  return nearest;
}

std::optional<double> escape_heading_rad(const LaserScan& scan, double within_m) {
  Eigen::Vector2d push(0, 0);
  for (const Eigen::Vector2f& p : scan_to_points(scan)) {
    const double d = p.norm();
    if (d > 1e-6 && d < within_m) push -= (within_m - d) * p.cast<double>() / d;
  }
  if (push.norm() < 1e-9) return std::nullopt;
  return std::atan2(push.y(), push.x());
}

PathFollower::PathFollower(const PathFollowerOptions& options) : options_(options) {}

double PathFollower::turn_rate(double heading_error_rad) const {
  return std::clamp(options_.turn_gain * heading_error_rad, -options_.max_turn_radps, options_.max_turn_radps);
}

void PathFollower::set_path(std::vector<Eigen::Vector2d> path_m) {
  path_ = std::move(path_m);
  progress_ = 0;
}

std::vector<Eigen::Vector2d> PathFollower::path_ahead(size_t max_points, double tolerance_m) const {
  CAIRN_CHECK(max_points >= 2, "a path needs its start and its end");
  if (path_.size() < 2 || progress_ + 1 >= path_.size()) return {};
  const std::vector<Eigen::Vector2d> corners =
      simplify_polyline({path_.begin() + std::ptrdiff_t(progress_), path_.end()}, tolerance_m);
  const size_t n = corners.size();
  if (n <= max_points) return corners;
  std::vector<Eigen::Vector2d> out;
  for (size_t k = 0; k < max_points; ++k) out.push_back(corners[(k * (n - 1)) / (max_points - 1)]);  // ends kept
  return out;
}

Eigen::Vector2d PathFollower::project(const Eigen::Vector2d& p) {
  if (path_.size() < 2) return path_.empty() ? p : path_[0];
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_point = path_[progress_];
  const size_t last = std::min(path_.size() - 1, progress_ + kProjectionWindow);
  for (size_t i = progress_; i < last; ++i) {
    const Eigen::Vector2d q = closest_on_segment(path_[i], path_[i + 1], p);
    const double d = (q - p).squaredNorm();
    if (d < best) {
      best = d;
      best_point = q;
      progress_ = i;
    }
  }
  return best_point;
}

Eigen::Vector2d PathFollower::along(const Eigen::Vector2d& from, double distance_m) const {
  Eigen::Vector2d at = from;
  for (size_t i = progress_ + 1; i < path_.size(); ++i) {
    const double step = (path_[i] - at).norm();
    if (step >= distance_m) return at + (path_[i] - at) * (distance_m / step);
    distance_m -= step;
    at = path_[i];
  }
  return path_.back();
}

double PathFollower::remaining_from(const Eigen::Vector2d& from) const {
  double total = 0;
  Eigen::Vector2d at = from;
  for (size_t i = progress_ + 1; i < path_.size(); ++i) {
    total += (path_[i] - at).norm();
    at = path_[i];
  }
  return total;
}

FollowerOutput PathFollower::update(const SE2& T_local_base, const LaserScan& scan) {
  const PathFollowerOptions& o = options_;
  FollowerOutput out;
  out.obstacle_ahead_m = obstacle_ahead_m(scan, o.robot_radius_m, o.robot_radius_m + o.side_margin_m);
  if (path_.empty()) return out;
  const Eigen::Vector2d position = T_local_base.translation();
  const Eigen::Vector2d projection = project(position);
  out.remaining_m = remaining_from(projection);
  out.lookahead_m = along(projection, o.lookahead_m);
  const Eigen::Vector2d target = T_local_base.inverse() * out.lookahead_m;  // base frame
  const double d = target.norm();
  if (d < o.end_reached_m && out.remaining_m < o.end_reached_m) return out;  // at the end: stop
  if (escape_) {
    if ((position - escape_->from_m).norm() < o.escape_m) {
      escape_step(T_local_base, scan, &out);
      if (escape_) return out;
    }
    escape_.reset();
  }
  out.heading_error_rad = std::atan2(target.y(), target.x());
  const double alpha = out.heading_error_rad;
  const double rotate = turn_rate(alpha);
  if (std::abs(alpha) > o.turn_in_place_rad) {
    out.command.angular_radps = rotate;
    return out;
  }
  // Speed: the least of the maximum, the ramp towards the end and the ramp towards returns ahead.
  double v = o.max_speed_mps;
  v = std::min(v, std::max(o.min_speed_mps, o.max_speed_mps * out.remaining_m / o.goal_slowdown_m));
  const double ramp_m = std::max(1e-6, o.slow_distance_m - o.safety_distance_m);
  v = std::min(v, std::max(o.min_speed_mps, o.max_speed_mps * (out.obstacle_ahead_m - o.safety_distance_m) / ramp_m));
  if (nearest_obstacle_m(scan, o.robot_radius_m) < o.near_obstacle_m) v = std::max(o.min_speed_mps, 0.5 * v);
  // Stop only for what the disc would hit driving on along its arc: a return beside it, in the
  // corridor's side margin or off the arc, slows it but never stops it (a robot parked a few
  // centimetres from rubble would otherwise stay blocked in every heading that keeps the rubble at
  // its side, and a path bending round a corner would stop at the corner).
  double curvature = 2.0 * target.y() / (d * d);
  if (free_travel_m(scan, o.robot_radius_m, curvature, o.safety_distance_m) <= o.safety_distance_m) {
    // Pure pursuit cuts corners: before stopping, hug the path with shorter lookaheads, slowly.
    bool hugging = false;
    for (double l = 0.5 * o.lookahead_m; l >= kMinLookaheadM && !hugging; l *= 0.5) {
      const Eigen::Vector2d t = T_local_base.inverse() * along(projection, l);
      const double k = 2.0 * t.y() / std::max(1e-6, t.squaredNorm());
      if (std::abs(std::atan2(t.y(), t.x())) > o.turn_in_place_rad) continue;
      if (free_travel_m(scan, o.robot_radius_m, k, o.safety_distance_m) <= o.safety_distance_m) continue;
      curvature = k;
      v = o.min_speed_mps;
      hugging = true;
    }
    if (!hugging) {
      out.blocked = true;  // stop; turning towards the path is still allowed
      out.command.angular_radps = rotate;
      // Pressed against a return (rubble a centimetre from its side: within the laser's noise, so
      // no arc along it is free), it first steps away from what it touches, towards the middle.
      if (!blocked_since_ns_) blocked_since_ns_ = scan.stamp_ns;
      const bool long_blocked = ns_to_sec(scan.stamp_ns - *blocked_since_ns_) >= o.escape_after_s;
      if (long_blocked && nearest_obstacle_m(scan, o.robot_radius_m) < o.contact_m) {
        if (const auto away = escape_heading_rad(scan, o.robot_radius_m + o.near_obstacle_m)) {
          escape_ = Escape{position, T_local_base.yaw() + *away};
          blocked_since_ns_.reset();
          escape_step(T_local_base, scan, &out);
        }
      }
      return out;
    }
  }
  blocked_since_ns_.reset();
  // Pure pursuit: the arc through the robot and the target, tangent to the heading.
  double w = v * curvature;
  if (std::abs(w) > o.max_turn_radps) {
    v = o.max_turn_radps / std::abs(curvature);
    w = std::copysign(o.max_turn_radps, curvature);
  }
  out.command.linear_mps = v;
  out.command.angular_radps = w;
  return out;
}

void PathFollower::escape_step(const SE2& T_local_base, const LaserScan& scan, FollowerOutput* out) {
  const PathFollowerOptions& o = options_;
  constexpr double kAlignedRad = 0.2;  // drive once the heading is this near the escape's
  const double error = normalize_angle(escape_->heading_rad - T_local_base.yaw());
  out->escaping = true;
  out->command = VelocityCommand{};
  if (std::abs(error) > kAlignedRad) {
    out->command.angular_radps = turn_rate(error);
    return;
  }
  // Done once the push turns back (in the middle, between the returns on either side), when
  // nothing is near any more, or when the way is not free.
  const auto away = escape_heading_rad(scan, o.robot_radius_m + o.near_obstacle_m);
  const double left_m = o.escape_m - (T_local_base.translation() - escape_->from_m).norm();
  if (!away || std::abs(normalize_angle(*away - error)) > M_PI / 2 ||
      free_travel_m(scan, o.robot_radius_m, 0.0, left_m) <= left_m) {
    escape_.reset();
    out->escaping = false;
    return;
  }
  out->command.linear_mps = o.min_speed_mps;
  out->command.angular_radps = turn_rate(error);
}

std::vector<Eigen::Vector2d> simplify_polyline(const std::vector<Eigen::Vector2d>& points, double tolerance_m) {
  CAIRN_CHECK(tolerance_m >= 0, "a simplification tolerance is not negative");
  if (points.size() <= 2) return points;
  std::vector<bool> keep(points.size(), false);
  keep.front() = keep.back() = true;
  std::vector<std::pair<size_t, size_t>> spans{{0, points.size() - 1}};  // explicit stack: no deep recursion
  while (!spans.empty()) {
    const auto [first, last] = spans.back();
    spans.pop_back();
    double worst = -1;
    size_t at = first;
    for (size_t i = first + 1; i < last; ++i) {
      const double d = (closest_on_segment(points[first], points[last], points[i]) - points[i]).norm();
      if (d > worst) worst = d, at = i;
    }
    if (worst <= tolerance_m) continue;
    keep[at] = true;
    spans.push_back({first, at});
    spans.push_back({at, last});
  }
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < points.size(); ++i)
    if (keep[i]) out.push_back(points[i]);
  return out;
}

}  // namespace cairn::agent

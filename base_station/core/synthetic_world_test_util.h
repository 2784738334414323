#pragma once
// Test-only: a synthetic rectangular room with one interior wall, analytic laser ray casting and
// keyframe/object generators for robots driving known paths. Header-only, used by the tests.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/keyframe.h"
#include "common/object_report.h"

namespace cairn::base::testing {

struct Segment {
  Eigen::Vector2d a, b;
};

/// Room [0, 10] x [0, 6] m with an interior wall x = 5, y in [0, 2.5].
inline std::vector<Segment> room_walls() {
  return {{{0, 0}, {10, 0}}, {{10, 0}, {10, 6}}, {{10, 6}, {0, 6}}, {{0, 6}, {0, 0}}, {{5, 0}, {5, 2.5}}};
}

/// Distance along a ray to the nearest wall, +inf if none.
inline double ray_cast_m(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir, const std::vector<Segment>& walls) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : walls) {
    const Eigen::Vector2d e = s.b - s.a;
    const double den = dir.x() * (-e.y()) + e.x() * dir.y();
    if (std::abs(den) < 1e-12) continue;
    const Eigen::Vector2d w = s.a - origin;
    const double t = (w.x() * (-e.y()) + e.x() * w.y()) / den;   // along the ray
    const double u = (dir.x() * w.y() - dir.y() * w.x()) / den;  // along the segment
    if (t > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

inline LaserScan simulate_scan(const SE2& T_world_base, const std::vector<Segment>& walls, float range_max_m = 8.f) {
  LaserScan scan;
  scan.angle_min_rad = float(-M_PI);
  scan.angle_increment_rad = float(2.0 * M_PI / 360.0);
  scan.range_max_m = range_max_m;
  for (int i = 0; i < 360; ++i) {
    const double a = T_world_base.yaw() + scan.angle_min_rad + i * scan.angle_increment_rad;
    const double r = ray_cast_m(T_world_base.translation(), {std::cos(a), std::sin(a)}, walls);
    scan.ranges_m.push_back(r >= range_max_m ? range_max_m : float(r));
  }
  return scan;
}

/// Poses every ~0.5 m along straight legs between waypoints, heading along each leg.
inline std::vector<SE2> along(const std::vector<Eigen::Vector2d>& waypoints) {
  std::vector<SE2> out;
  for (size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Eigen::Vector2d d = waypoints[i + 1] - waypoints[i];
    const int steps = std::max(1, int(std::round(d.norm() / 0.5)));
    for (int k = 0; k < steps; ++k) out.emplace_back(waypoints[i] + d * (double(k) / steps), std::atan2(d.y(), d.x()));
  }
  out.emplace_back(waypoints.back(), out.back().yaw());
  return out;
}

/// Keyframes of a robot following `path_world` (exact odometry), in its local frame whose origin
/// is path_world[0].
inline std::vector<Keyframe> make_keyframes(RobotId robot, const std::vector<SE2>& path_world,
                                            const std::vector<Segment>& walls) {
  std::vector<Keyframe> out;
  const SE2 T_local_world = path_world.front().inverse();
  for (size_t i = 0; i < path_world.size(); ++i) {
    Keyframe kf;
    kf.id = KeyframeId{robot, int32_t(i)};
    kf.stamp_ns = StampNs(i + 1) * kNsPerSec;
    kf.T_local_base = T_local_world * path_world[i];
    if (i > 0) kf.T_prev_this = path_world[i - 1].between(path_world[i]);
    kf.scan = simulate_scan(path_world[i], walls);
    out.push_back(kf);
  }
  return out;
}

/// Keyframes of a robot on `path_world` whose front end turns its heading by `yaw_drift_rad_per_m`
/// more than it really turned on every metre between keyframes `from` and `until`: the scans are
/// true, the poses bend.
inline std::vector<Keyframe> drifting_keyframes(RobotId robot, const std::vector<SE2>& path_world,
                                                const std::vector<Segment>& walls, double yaw_drift_rad_per_m,
                                                size_t from = 0, size_t until = SIZE_MAX) {
  std::vector<Keyframe> out = make_keyframes(robot, path_world, walls);
  for (size_t i = from + 1; i < out.size(); ++i) {
    const SE2 step = path_world[i - 1].between(path_world[i]);
    const double drift = i <= until ? yaw_drift_rad_per_m : 0.0;
    out[i].T_prev_this = SE2(step.x(), step.y(), step.yaw() + drift * step.translation().norm());
    out[i].T_local_base = out[i - 1].T_local_base * out[i].T_prev_this;
  }
  return out;
}

/// A report of an object at p_world seen from keyframe `anchor` (pose anchor_world), with a small
/// cubic cloud around it.
inline ObjectReport make_object(ObjectId id, const std::string& class_name, const Eigen::Vector3d& p_world,
                                int32_t anchor_seq, const SE2& anchor_world, int observations = 5) {
  ObjectReport r;
  r.id = id;
  r.class_name = class_name;
  r.confidence = 0.8f;
  r.stamp_ns = kNsPerSec * (anchor_seq + 1);
  r.anchor_seq = anchor_seq;
  r.T_anchor_object = anchor_world.to_isometry3().inverse() * Eigen::Translation3d(p_world);
  r.observations = observations;
  r.size_m = Eigen::Vector3f(0.3f, 0.3f, 0.3f);
  for (int i = -3; i <= 3; ++i) {
    for (int j = -3; j <= 3; ++j) {
      r.cloud.push_back(ColoredPoint{0.05f * i, 0.05f * j, 0.15f, 200, 50, 50});
    }
  }
  r.thumbnail_jpeg = {0xFF, 0xD8, 0xFF, 0xD9};
  return r;
}

/// A path through the room (14 keyframes, up the diagonal then back along the top).
inline std::vector<SE2> long_path() {
  std::vector<SE2> p;
  for (int i = 0; i < 8; ++i) p.push_back(SE2(1.5 + 0.4 * i, 1.0 + 0.4 * i, 0.2 * i));
  for (int i = 0; i < 6; ++i) p.push_back(SE2(4.3 - 0.5 * i, 4.5, 2.5 + 0.1 * i));
  return p;
}

/// The same path offset by (0.25, -0.2) m and turned by 0.6 rad: a second robot retracing it closes
/// loops with the first.
inline std::vector<SE2> retrace(const std::vector<SE2>& path) {
  std::vector<SE2> out;
  for (const SE2& p : path) out.push_back(SE2(p.x() + 0.25, p.y() - 0.2, p.yaw() + 0.6));
  return out;
}

/// Two paths through the room: robot 0 in the left half, robot 1 in the right half.
inline std::vector<SE2> left_path() {
  return {{1.5, 1.0, 0.0}, {2.5, 1.2, 0.3}, {3.5, 2.0, 1.0}, {3.5, 3.5, 1.57}, {2.5, 4.5, 2.5}, {1.2, 4.5, 3.1}};
}
inline std::vector<SE2> right_path() {
  return {{8.5, 1.0, 1.57}, {8.5, 2.5, 1.6}, {8.0, 4.0, 2.4}, {6.8, 4.6, 3.0}, {5.6, 4.2, -2.5}, {6.0, 3.0, -1.2}};
}

/// Building [0, 24] x [0, 10] m: a corridor y in [0, 2] along it, and two identical wings of two
/// rooms each north of it (wing W x in [0, 12], wing E = wing W shifted by +12 m).
inline std::vector<Segment> two_wing_building() {
  std::vector<Segment> w = {{{0, 0}, {24, 0}}, {{24, 0}, {24, 10}}, {{24, 10}, {0, 10}}, {{0, 10}, {0, 0}}};
  for (double ox : {0.0, 12.0}) {
    auto add = [&](double x0, double y0, double x1, double y1) { w.push_back({{ox + x0, y0}, {ox + x1, y1}}); };
    add(0, 2, 2.5, 2);  // corridor wall with doors at x 2.5..3.5 and 8.5..9.5
    add(3.5, 2, 8.5, 2);
    add(9.5, 2, 12, 2);
    if (ox > 0) add(0, 2, 0, 10);                                        // wing separator (x = 12)
    add(6, 2, 6, 10);                                                    // room divider
    add(1, 7, 2, 7), add(2, 7, 2, 8), add(2, 8, 1, 8), add(1, 8, 1, 7);  // a cabinet in room A
    add(7, 8, 9, 9.5);                                                   // a slanted wall in room B
  }
  return w;
}

/// A route through wing W's corridor and both rooms, shifted by ox along x (12: wing E).
inline std::vector<Eigen::Vector2d> west_route(double ox) {
  std::vector<Eigen::Vector2d> w = {{1.5, 1}, {3, 1}, {3, 5},    {1.5, 6}, {4.5, 6.5}, {3, 5}, {3, 1},
                                    {9, 1},   {9, 5}, {10.5, 7}, {8, 6.5}, {9, 5},     {9, 1}, {10.5, 1}};
  for (auto& p : w) p.x() += ox;
  return w;
}

}  // namespace cairn::base::testing

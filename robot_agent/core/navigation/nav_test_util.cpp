#include "robot_agent/core/navigation/nav_test_util.h"

#include <algorithm>
#include <cmath>

namespace cairn::agent::testing {

void add_box(std::vector<Segment>* w, double x0, double y0, double x1, double y1) {
  w->push_back({{x0, y0}, {x1, y0}});
  w->push_back({{x1, y0}, {x1, y1}});
  w->push_back({{x1, y1}, {x0, y1}});
  w->push_back({{x0, y1}, {x0, y0}});
}

void add_ring(std::vector<Segment>* w, const Eigen::Vector2d& centre, double radius_m, int sides) {
  for (int i = 0; i < sides; ++i) {
    const double a0 = 2 * M_PI * i / sides, a1 = 2 * M_PI * (i + 1) / sides;
    w->push_back({centre + radius_m * Eigen::Vector2d(std::cos(a0), std::sin(a0)),
                  centre + radius_m * Eigen::Vector2d(std::cos(a1), std::sin(a1))});
  }
}

double distance_to_walls(const std::vector<Segment>& world, const Eigen::Vector2d& p) {
  double best = 1e9;
  for (const Segment& s : world) {
    const Eigen::Vector2d d = s.b - s.a;
    const double t = std::clamp((p - s.a).dot(d) / std::max(1e-12, d.squaredNorm()), 0.0, 1.0);
    best = std::min(best, (s.a + t * d - p).norm());
  }
  return best;
}

std::vector<Segment> room_and_corridor() {
  std::vector<Segment> w;
  w.push_back({{0, 0}, {4, 0}});  // the room
  w.push_back({{0, 0}, {0, 4}});
  w.push_back({{0, 4}, {4, 4}});
  w.push_back({{4, 0}, {4, 1.5}});  // east wall, door y 1.5-2.5
  w.push_back({{4, 2.5}, {4, 4}});
  w.push_back({{4, 1.25}, {10, 1.25}});  // corridor east
  w.push_back({{4, 2.75}, {8.5, 2.75}});
  w.push_back({{10, 1.25}, {10, 7}});  // and north
  w.push_back({{8.5, 2.75}, {8.5, 7}});
  w.push_back({{8.5, 7}, {10, 7}});
  return w;
}

SE2 unicycle_step(const SE2& pose, const VelocityCommand& command, double dt_s) {
  const double mid_yaw = pose.yaw() + 0.5 * command.angular_radps * dt_s;
  const Eigen::Vector2d step = command.linear_mps * dt_s * Eigen::Vector2d(std::cos(mid_yaw), std::sin(mid_yaw));
  return SE2(pose.translation() + step, pose.yaw() + command.angular_radps * dt_s);
}

DriveResult drive(Navigator* nav, const std::vector<Segment>& world, SE2* pose, StampNs* stamp_ns,
                  const DriveOptions& o, const std::function<bool()>& until) {
  DriveResult result;
  const StampNs start_ns = *stamp_ns;
  while (nav->state() == NavState::kDriving && ns_to_sec(*stamp_ns - start_ns) < o.max_s && !(until && until())) {
    const LaserScan scan = ray_cast(world, *pose, *stamp_ns, o.num_beams);
    const VelocityCommand command = nav->update(*stamp_ns, *pose, scan);
    result.max_linear_mps = std::max(result.max_linear_mps, command.linear_mps);
    if (!o.frozen) {
      const SE2 next = unicycle_step(*pose, command, o.dt_s);
      result.travelled_m += (next.translation() - pose->translation()).norm();
      *pose = next;
    }
    result.min_wall_distance_m = std::min(result.min_wall_distance_m, distance_to_walls(world, pose->translation()));
    *stamp_ns += sec_to_ns(o.dt_s);
    ++result.steps;
  }
  result.seconds = ns_to_sec(*stamp_ns - start_ns);
  return result;
}

}  // namespace cairn::agent::testing

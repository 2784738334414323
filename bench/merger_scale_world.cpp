#include "bench/merger_scale_world.h"

#include <cmath>

namespace cairn::bench {
namespace {

using base::testing::Segment;

void add_wall(const Eigen::Vector2d& a, const Eigen::Vector2d& b, int kind, std::vector<Segment>* walls) {
  if (kind == 0) return;  // open
  if (kind == 2) {        // closed
    walls->push_back({a, b});
    return;
  }
  const Eigen::Vector2d mid = 0.5 * (a + b), dir = (b - a).normalized();
  walls->push_back({a, mid - 0.8 * dir});
  walls->push_back({mid + 0.8 * dir, b});
}

void plan_next_room(const Building& b, std::mt19937* rng, Walker* w) {
  std::vector<std::pair<int, int>> next;
  if (w->x + 1 < kRoomsX && b.pass[w->x][w->y][0]) next.push_back({w->x + 1, w->y});
  if (w->y + 1 < kRoomsY && b.pass[w->x][w->y][1]) next.push_back({w->x, w->y + 1});
  if (w->x > 0 && b.pass[w->x - 1][w->y][0]) next.push_back({w->x - 1, w->y});
  if (w->y > 0 && b.pass[w->x][w->y - 1][1]) next.push_back({w->x, w->y - 1});
  if (next.empty()) next.push_back({w->x, w->y});
  const auto [nx, ny] = next[std::uniform_int_distribution<size_t>(0, next.size() - 1)(*rng)];
  const Eigen::Vector2d from = w->true_pose.translation(), to((nx + 0.5) * kRoomM, (ny + 0.5) * kRoomM);
  const double yaw = (to - from).norm() > 1e-6 ? std::atan2(to.y() - from.y(), to.x() - from.x()) : w->true_pose.yaw();
  const int steps = std::max(1, int(std::round((to - from).norm() / 0.5)));
  for (int i = 1; i <= steps; ++i) w->plan.push_back(SE2(from + (to - from) * double(i) / steps, yaw));
  w->x = nx;
  w->y = ny;
}

}  // namespace

Building make_building(std::mt19937* rng) {
  Building b;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double W = kRoomsX * kRoomM, H = kRoomsY * kRoomM;
  b.walls = {{{0, 0}, {W, 0}}, {{W, 0}, {W, H}}, {{W, H}, {0, H}}, {{0, H}, {0, 0}}};
  for (int x = 0; x < kRoomsX; ++x) {
    for (int y = 0; y < kRoomsY; ++y) {
      const Eigen::Vector2d c0(x * kRoomM, y * kRoomM);
      for (int dir = 0; dir < 2; ++dir) {
        if ((dir == 0 && x + 1 == kRoomsX) || (dir == 1 && y + 1 == kRoomsY)) continue;
        const double r = u(*rng);
        const int kind = r < 0.15 ? 0 : r < 0.85 ? 1 : 2;
        b.pass[x][y][dir] = kind != 2;
        const Eigen::Vector2d a = dir == 0 ? c0 + Eigen::Vector2d(kRoomM, 0) : c0 + Eigen::Vector2d(0, kRoomM);
        add_wall(a, a + (dir == 0 ? Eigen::Vector2d(0, kRoomM) : Eigen::Vector2d(kRoomM, 0)), kind, &b.walls);
      }
      if (u(*rng) < 0.5) {  // a pillar (0.4 - 1.2 m square) off the room's centre lines
        const double s = 0.4 + 0.8 * u(*rng);
        const Eigen::Vector2d p = c0 + Eigen::Vector2d(1.5 + 1.5 * u(*rng), 1.5 + 1.5 * u(*rng));
        const Eigen::Vector2d q = p + Eigen::Vector2d(s, s);
        b.walls.push_back({p, {q.x(), p.y()}});
        b.walls.push_back({{q.x(), p.y()}, q});
        b.walls.push_back({q, {p.x(), q.y()}});
        b.walls.push_back({{p.x(), q.y()}, p});
      }
    }
  }
  return b;
}

Keyframe next_loop_keyframe(const Building& b, std::mt19937* rng, RobotId robot, Walker* w) {
  if (w->plan.empty()) plan_next_room(b, rng, w);
  const SE2 next = w->plan.front();
  w->plan.erase(w->plan.begin());
  std::normal_distribution<double> n_xy(0.0, 0.01), n_yaw(0.0, 0.003);
  const SE2 step = w->true_pose.between(next);
  const SE2 measured = step * SE2(n_xy(*rng), n_xy(*rng), n_yaw(*rng));
  std::vector<Segment> near;  // walls within scan range: the ray cast stays cheap
  for (const Segment& s : b.walls) {
    const Eigen::Vector2d lo = s.a.cwiseMin(s.b).array() - 9.0, hi = s.a.cwiseMax(s.b).array() + 9.0;
    const Eigen::Vector2d p = next.translation();
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) near.push_back(s);
  }
  Keyframe kf;
  kf.id = KeyframeId{robot, w->seq};
  kf.stamp_ns = StampNs(w->seq + 1) * kNsPerSec;
  kf.T_prev_this = measured;
  kf.T_local_base = w->local_pose * measured;
  kf.edge_covariance = Covariance3(Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal());
  kf.scan = base::testing::simulate_scan(next, near);
  w->true_pose = next;
  w->local_pose = kf.T_local_base;
  ++w->seq;
  return kf;
}

Keyframe make_keyframe(RobotId robot, int seq, const SE2& prev, const SE2& pose) {
  constexpr int kBeams = 90;
  Keyframe kf;
  kf.id = KeyframeId{robot, seq};
  kf.stamp_ns = StampNs(seq + 1) * kNsPerSec;
  kf.T_local_base = pose;
  kf.T_prev_this = prev.between(pose);
  kf.edge_covariance = Covariance3::Identity() * 1e-3;
  kf.scan.angle_min_rad = float(-M_PI);
  kf.scan.angle_increment_rad = float(2 * M_PI / kBeams);
  kf.scan.range_max_m = 12.f;
  for (int i = 0; i < kBeams; ++i) kf.scan.ranges_m.push_back(3.f + 0.5f * float(std::sin(0.1 * i + seq)));
  return kf;
}

}  // namespace cairn::bench

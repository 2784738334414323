// The earliest moment each robot of a world could possibly be linked to the team's map: a physical
// lower bound that no linking method can beat, to read the measured times to link against.
//
// Every robot drives from t = 0 at its top speed along the shortest drivable way on the true floor
// plan (a disc of the simulator's robot radius), though no robot knows that way at the start. Two
// robots can have evidence to link on no sooner than the first of:
//  - a sighting: one within the camera's depth range of the other, in line of sight (facing ignored);
//  - a shared view: `shared_wall_cells` wall cells (1 m of wall) that both lasers could have hit.
// A robot joins the map through a chain of such pairs to the anchor (the lowest id), so its bound is
// L(anchor) = 0, L(r) = min over teammates b of max(pair(r, b), L(b)) (a Dijkstra with max).
//
// Written here rather than with a library: it is a few grid searches over the simulator's own
// FloorPlan and its ray caster, which no graph library would shorten.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "common/errors.h"
#include "sim/world.h"

namespace {

using cairn::sim::FloorPlan;
using cairn::sim::WorldFile;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct BoundOptions {
  double node_step_m = 0.2;    ///< grid of places a robot can be
  int rays = 180;              ///< directions looked in from each place
  int shared_wall_cells = 20;  ///< what a shared view needs (1 m of wall at 0.05 m)
  /// An 8-connected grid path is up to 1/cos(22.5 deg) longer than the straight way: distances are
  /// divided by it, so the grid never makes a bound later than it is.
  double octile_factor = 1.0 / std::cos(M_PI / 8.0);
};

/// Places a robot (a disc) fits, on a grid of node_step_m, with the drive time to each from a start.
class DriveTimes {
 public:
  DriveTimes(const FloorPlan& plan, double radius_m, const BoundOptions& options)
      : plan_(plan), step_(options.node_step_m) {
    const Eigen::Vector2d size = plan.max_m() - plan.origin_m();
    cols_ = int(size.x() / step_);
    rows_ = int(size.y() / step_);
    fits_.resize(size_t(cols_ * rows_));
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c) fits_[index(c, r)] = plan.disc_free(centre(c, r), radius_m);
    octile_factor_ = options.octile_factor;
  }
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  size_t index(int c, int r) const { return size_t(r * cols_ + c); }
  Eigen::Vector2d centre(int c, int r) const { return plan_.origin_m() + step_ * Eigen::Vector2d(c + 0.5, r + 0.5); }
  bool fits(int c, int r) const { return c >= 0 && r >= 0 && c < cols_ && r < rows_ && fits_[index(c, r)]; }
  /// Node index under p, or -1 when p is off the grid or the robot does not fit there.
  long node_at(const Eigen::Vector2d& p_m) const {
    const Eigen::Vector2d q = (p_m - plan_.origin_m()) / step_;
    const int c = int(std::floor(q.x())), r = int(std::floor(q.y()));
    return fits(c, r) ? long(index(c, r)) : -1;
  }

  /// Seconds to each node at speed_mps from start (kInf where it cannot drive).
  std::vector<double> seconds_from(const Eigen::Vector2d& start_m, double speed_mps) const {
    std::vector<double> metres(fits_.size(), kInf);
    const long start = node_at(start_m);
    if (start < 0) throw cairn::InputError("bench_link_bound: a robot's start has no room for the robot");
    using Item = std::pair<double, long>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    metres[size_t(start)] = 0.0;
    queue.push({0.0, start});
    while (!queue.empty()) {
      const auto [d, i] = queue.top();
      queue.pop();
      if (d > metres[size_t(i)]) continue;
      const int c = int(i % cols_), r = int(i / cols_);
      for (int dc = -1; dc <= 1; ++dc)
        for (int dr = -1; dr <= 1; ++dr) {
          if ((dc == 0 && dr == 0) || !fits(c + dc, r + dr)) continue;
          if (dc != 0 && dr != 0 && (!fits(c + dc, r) || !fits(c, r + dr))) continue;  // no corner cutting
          const double nd = d + step_ * std::hypot(dc, dr);
          const size_t j = index(c + dc, r + dr);
          if (nd < metres[j]) {
            metres[j] = nd;
            queue.push({nd, long(j)});
          }
        }
    }
    for (double& m : metres) m = m / octile_factor_ / speed_mps;
    return metres;
  }

 private:
  const FloorPlan& plan_;
  double step_;
  int cols_ = 0, rows_ = 0;
  double octile_factor_ = 1.0;
  std::vector<bool> fits_;
};

/// Per wall cell of the plan: the first second the robot's laser could have hit it.
std::vector<double> wall_seen_s(const FloorPlan& plan, const DriveTimes& grid, const std::vector<double>& t_s,
                                double laser_range_m, const BoundOptions& options) {
  std::vector<double> seen(size_t(plan.width()) * size_t(plan.height()), kInf);
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const double t = t_s[grid.index(c, r)];
      if (!std::isfinite(t)) continue;
      for (int k = 0; k < options.rays; ++k) {
        const auto hit = plan.cast_ray(grid.centre(c, r), 2.0 * M_PI * k / options.rays, laser_range_m);
        if (!hit.hit) continue;
        double& s = seen[size_t(hit.row) * size_t(plan.width()) + size_t(hit.col)];
        s = std::min(s, t);
      }
    }
  return seen;
}

/// Per node: the first second the other robot could be within range_m of it in line of sight.
std::vector<double> in_sight_s(const FloorPlan& plan, const DriveTimes& grid, const std::vector<double>& other_t_s,
                               double range_m, const BoundOptions& options) {
  std::vector<double> out(other_t_s.size(), kInf);
  const double step_m = 0.5 * options.node_step_m;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      if (!grid.fits(c, r)) continue;
      const Eigen::Vector2d p = grid.centre(c, r);
      double best = other_t_s[grid.index(c, r)];
      for (int k = 0; k < options.rays; ++k) {
        const double a = 2.0 * M_PI * k / options.rays;
        const Eigen::Vector2d dir(std::cos(a), std::sin(a));
        const double reach = std::min(range_m, plan.cast_ray_dir(p, dir, range_m).range_m);
        for (double s = step_m; s <= reach; s += step_m) {
          const long q = grid.node_at(p + s * dir);
          if (q >= 0) best = std::min(best, other_t_s[size_t(q)]);
        }
      }
      out[grid.index(c, r)] = best;
    }
  return out;
}

double kth_smallest_max(const std::vector<double>& a, const std::vector<double>& b, int k) {
  std::vector<double> both;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(b[i])) both.push_back(std::max(a[i], b[i]));
  if (int(both.size()) < k) return kInf;
  std::nth_element(both.begin(), both.begin() + (k - 1), both.end());
  return both[size_t(k - 1)];
}

double min_max(const std::vector<double>& a, const std::vector<double>& b) {
  double best = kInf;
  for (size_t i = 0; i < a.size(); ++i) best = std::min(best, std::max(a[i], b[i]));
  return best;
}

std::string seconds(double s) {
  if (!std::isfinite(s)) return "never";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", s);
  return text;
}

int run(const std::string& world_path, const BoundOptions& options) {
  const WorldFile file = cairn::sim::load_world_file(world_path);
  const FloorPlan& plan = file.world.floor_plan;
  const auto& robots = file.world.robots;
  const DriveTimes grid(plan, file.sim.robot_radius_m, options);
  std::vector<std::vector<double>> t_s, seen_s;
  for (const auto& robot : robots) {
    t_s.push_back(grid.seconds_from(robot.T_world_start.translation(), robot.max_speed_mps));
    seen_s.push_back(wall_seen_s(plan, grid, t_s.back(), file.sim.laser.max_range_m, options));
  }
  const size_t n = robots.size();
  std::vector<std::vector<double>> pair_s(n, std::vector<double>(n, kInf)), sight_s = pair_s, view_s = pair_s;
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      sight_s[a][b] = sight_s[b][a] =
          min_max(t_s[a], in_sight_s(plan, grid, t_s[b], file.sim.camera.max_depth_m, options));
      view_s[a][b] = view_s[b][a] = kth_smallest_max(seen_s[a], seen_s[b], options.shared_wall_cells);
      pair_s[a][b] = pair_s[b][a] = std::min(sight_s[a][b], view_s[a][b]);
    }
  // Dijkstra with max from the anchor: the earliest each robot can join the anchor's map.
  std::vector<double> link_s(n, kInf);
  std::vector<bool> done(n, false);
  link_s[0] = 0.0;
  for (size_t round = 0; round < n; ++round) {
    size_t next = n;
    for (size_t i = 0; i < n; ++i)
      if (!done[i] && (next == n || link_s[i] < link_s[next])) next = i;
    done[next] = true;
    for (size_t j = 0; j < n; ++j)
      if (!done[j]) link_s[j] = std::min(link_s[j], std::max(link_s[next], pair_s[next][j]));
  }
  std::printf("%s: earliest possible link (robots at top speed on the shortest ways from t = 0)\n",
              file.world.name.c_str());
  std::printf("robot  first sighting  first shared view  earliest link\n");
  std::vector<double> others;
  for (size_t i = 0; i < n; ++i) {
    double sight = kInf, view = kInf;
    for (size_t j = 0; j < n; ++j) sight = std::min(sight, sight_s[i][j]), view = std::min(view, view_s[i][j]);
    std::printf("%5d  %14s  %17s  %13s%s\n", robots[i].id.value, seconds(sight).c_str(), seconds(view).c_str(),
                seconds(link_s[i]).c_str(), i == 0 ? " (anchor)" : "");
    if (i > 0) others.push_back(link_s[i]);
  }
  if (!others.empty()) {
    std::sort(others.begin(), others.end());
    const size_t m = others.size();
    const double median = m % 2 ? others[m / 2] : 0.5 * (others[m / 2 - 1] + others[m / 2]);
    std::printf("median over the robots that must be linked: %s\n", seconds(median).c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Earliest moment each robot of a world could be linked: a physical lower bound"};
  std::vector<std::string> worlds;
  BoundOptions options;
  app.add_option("worlds", worlds, "world YAML files")->required()->check(CLI::ExistingFile);
  app.add_option("--shared-wall-cells", options.shared_wall_cells, "wall cells both lasers must have hit")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    for (const auto& world : worlds) run(world, options);
  } catch (const cairn::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}

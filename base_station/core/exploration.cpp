#include "base_station/core/exploration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "base_station/core/merged_map.h"

namespace cairn::base {
namespace {

enum class Cell : uint8_t { kUnknown, kFree, kOccupied };

/// The part of the map worth planning in: the known cells' bounding box plus one unknown cell all
/// round (the global map grows in large blocks, mostly unknown). Cell (0, 0) is the map's
/// (col0, row0).
struct Grid {
  int col0 = 0, row0 = 0, w = 0, h = 0;
  double res = 0;
  std::vector<Cell> cells;
  std::vector<uint8_t> near_wall;
  bool in(int c, int r) const { return c >= 0 && r >= 0 && c < w && r < h; }
  size_t at(int c, int r) const { return size_t(r) * w + c; }
  Eigen::Vector2d centre_m(const OccupancyGrid& map, const Eigen::Vector2i& cell) const {
    return map.cell_center_m(cell.x() + col0, cell.y() + row0);
  }
  Eigen::Vector2i cell_of(const OccupancyGrid& map, const Eigen::Vector2d& p_m) const {
    return map.cell_of(p_m) - Eigen::Vector2i(col0, row0);
  }
};

Grid classify(const OccupancyGrid& grid, const ExplorationOptions& o) {
  Grid g;
  int col1 = -1, row1 = -1;
  g.col0 = grid.width();
  g.row0 = grid.height();
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) {
      if (!grid.known(c, r)) continue;
      g.col0 = std::min(g.col0, c);
      g.row0 = std::min(g.row0, r);
      col1 = std::max(col1, c);
      row1 = std::max(row1, r);
    }
  }
  g.res = grid.resolution_m();
  if (col1 < 0) return g;  // nothing known: an empty grid
  g.col0 -= 1;
  g.row0 -= 1;
  g.w = col1 - g.col0 + 2;
  g.h = row1 - g.row0 + 2;
  g.cells.assign(size_t(g.w) * g.h, Cell::kUnknown);
  for (int r = 0; r < g.h; ++r) {
    for (int c = 0; c < g.w; ++c) {
      if (!grid.known(c + g.col0, r + g.row0)) continue;  // also what lies outside the map
      const double p = grid.probability(c + g.col0, r + g.row0);
      g.cells[g.at(c, r)] = p > o.occupied_above ? Cell::kOccupied : p < o.free_below ? Cell::kFree : Cell::kUnknown;
    }
  }
  // Cells within the clearance of a wall (a square dilation, separable: rows, then columns).
  const int k = std::max(0, int(std::ceil(o.clearance_m / g.res)));
  std::vector<uint8_t> rows(g.cells.size(), 0);
  for (int r = 0; r < g.h; ++r) {
    int last_wall = -1000000;
    for (int c = 0; c < g.w; ++c) {
      if (g.cells[g.at(c, r)] == Cell::kOccupied) last_wall = c;
      if (c - last_wall <= k) rows[g.at(c, r)] = 1;
    }
    last_wall = 1000000;
    for (int c = g.w - 1; c >= 0; --c) {
      if (g.cells[g.at(c, r)] == Cell::kOccupied) last_wall = c;
      if (last_wall - c <= k) rows[g.at(c, r)] = 1;
    }
  }
  g.near_wall.assign(g.cells.size(), 0);
  for (int c = 0; c < g.w; ++c) {
    int last = -1000000;
    for (int r = 0; r < g.h; ++r) {
      if (rows[g.at(c, r)]) last = r;
      if (r - last <= k) g.near_wall[g.at(c, r)] = 1;
    }
    last = 1000000;
    for (int r = g.h - 1; r >= 0; --r) {
      if (rows[g.at(c, r)]) last = r;
      if (last - r <= k) g.near_wall[g.at(c, r)] = 1;
    }
  }
  return g;
}

bool is_frontier(const Grid& g, int c, int r) {
  if (g.cells[g.at(c, r)] != Cell::kFree) return false;
  constexpr int kN[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& d : kN) {
    const int cc = c + d[0], rr = r + d[1];
    if (!g.in(cc, rr) || g.cells[g.at(cc, rr)] == Cell::kUnknown) return true;
  }
  return false;
}

/// Connected pieces of frontier cells (8-neighbours), as cell lists.
std::vector<std::vector<Eigen::Vector2i>> frontier_pieces(const Grid& g) {
  std::vector<uint8_t> seen(g.cells.size(), 0);
  std::vector<std::vector<Eigen::Vector2i>> pieces;
  for (int r = 0; r < g.h; ++r) {
    for (int c = 0; c < g.w; ++c) {
      if (seen[g.at(c, r)] || !is_frontier(g, c, r)) continue;
      std::vector<Eigen::Vector2i> piece{{c, r}};
      seen[g.at(c, r)] = 1;
      for (size_t i = 0; i < piece.size(); ++i) {
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const int cc = piece[i].x() + dc, rr = piece[i].y() + dr;
            if (!g.in(cc, rr) || seen[g.at(cc, rr)] || !is_frontier(g, cc, rr)) continue;
            seen[g.at(cc, rr)] = 1;
            piece.emplace_back(cc, rr);
          }
        }
      }
      pieces.push_back(std::move(piece));
    }
  }
  return pieces;
}

/// Path lengths (m) from `start` through free cells, 8-connected, dearer near walls (Dijkstra).
/// A start cell that is not free (the robot stands on a cell the map calls unknown or a wall's
/// edge) starts from the nearest free cell within 0.5 m.
std::vector<double> path_lengths(const Grid& g, Eigen::Vector2i start, const ExplorationOptions& o) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(g.cells.size(), kInf);
  if (!g.in(start.x(), start.y()) || g.cells[g.at(start.x(), start.y())] != Cell::kFree) {
    const int k = int(std::ceil(0.5 / g.res));
    double best = kInf;
    Eigen::Vector2i found(-1, -1);
    for (int dr = -k; dr <= k; ++dr) {
      for (int dc = -k; dc <= k; ++dc) {
        const int c = start.x() + dc, r = start.y() + dr;
        if (g.in(c, r) && g.cells[g.at(c, r)] == Cell::kFree && std::hypot(dc, dr) < best) {
          best = std::hypot(dc, dr);
          found = {c, r};
        }
      }
    }
    if (found.x() < 0) return dist;
    start = found;
  }
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[g.at(start.x(), start.y())] = 0;
  queue.push({0.0, g.at(start.x(), start.y())});
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    const int c = int(i % g.w), r = int(i / g.w);
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int cc = c + dc, rr = r + dr;
        if ((dc == 0 && dr == 0) || !g.in(cc, rr)) continue;
        const size_t j = g.at(cc, rr);
        if (g.cells[j] != Cell::kFree) continue;
        const double step = g.res * (dc && dr ? M_SQRT2 : 1.0) * (g.near_wall[j] ? o.near_wall_cost : 1.0);
        if (d + step < dist[j]) {
          dist[j] = d + step;
          queue.push({dist[j], j});
        }
      }
    }
  }
  return dist;
}

}  // namespace

ExplorationPlan plan_exploration(const OccupancyGrid& grid, const std::map<RobotId, Eigen::Vector2d>& robots_m,
                                 const std::vector<Eigen::Vector2d>& victims_m, const ExplorationOptions& o) {
  ExplorationPlan plan;
  if (grid.width() == 0 || grid.height() == 0) {
    for (const auto& [robot, p] : robots_m) plan.idle.push_back(robot);
    return plan;
  }
  const Grid g = classify(grid, o);
  std::vector<std::vector<Eigen::Vector2i>> pieces = frontier_pieces(g);
  pieces.erase(
      std::remove_if(pieces.begin(), pieces.end(), [&](const auto& p) { return int(p.size()) < o.min_frontier_cells; }),
      pieces.end());
  std::sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (const auto& piece : pieces) {
    Frontier f;
    f.cells = int(piece.size());
    f.length_m = f.cells * g.res;
    Eigen::Vector2d mean(0, 0);
    int near_victim = 0;
    for (const auto& cell : piece) {
      const Eigen::Vector2d p = g.centre_m(grid, cell);
      mean += p;
      for (const auto& v : victims_m) {
        if ((p - v).norm() <= o.victim_radius_m) {
          ++near_victim;
          break;
        }
      }
    }
    mean /= double(piece.size());
    double best = std::numeric_limits<double>::infinity();
    for (const auto& cell : piece) {
      const Eigen::Vector2d p = g.centre_m(grid, cell);
      if ((p - mean).norm() < best) {
        best = (p - mean).norm();
        f.centre_m = p;
      }
    }
    f.weight = 1.0 + o.victim_weight * double(near_victim) / double(piece.size());
    plan.frontiers.push_back(f);
  }

  // Every robot's best (nearest along free space) cell of every frontier.
  struct Option {
    RobotId robot;
    int frontier;
    Eigen::Vector2d goal_m;
    double path_m, utility;
  };
  std::vector<Option> options;
  for (const auto& [robot, position] : robots_m) {
    const std::vector<double> dist = path_lengths(g, g.cell_of(grid, position), o);
    for (size_t f = 0; f < pieces.size(); ++f) {
      double best = std::numeric_limits<double>::infinity();
      Eigen::Vector2i best_cell;
      for (const auto& cell : pieces[f]) {
        const double d = dist[g.at(cell.x(), cell.y())];
        if (d < best) {
          best = d;
          best_cell = cell;
        }
      }
      if (!std::isfinite(best)) continue;
      const Frontier& fr = plan.frontiers[f];
      options.push_back({robot, int(f), g.centre_m(grid, best_cell), best, fr.weight * fr.length_m / (best + 1.0)});
    }
  }
  // Greedy: the best (robot, frontier) pair first; then neither that robot nor any frontier goal
  // within the separation of the chosen one is offered again.
  std::sort(options.begin(), options.end(), [](const Option& a, const Option& b) { return a.utility > b.utility; });
  std::map<RobotId, bool> assigned;
  for (const Option& opt : options) {
    if (assigned[opt.robot]) continue;
    bool crowded = false;
    for (const ExplorationGoal& goal : plan.goals) {
      crowded = crowded || goal.frontier == opt.frontier || (goal.goal_m - opt.goal_m).norm() < o.separation_m;
    }
    if (crowded) continue;
    assigned[opt.robot] = true;
    plan.goals.push_back({opt.robot, opt.frontier, opt.goal_m, opt.path_m, opt.utility});
  }
  for (const auto& [robot, position] : robots_m) {
    if (!assigned[robot]) plan.idle.push_back(robot);
  }
  return plan;
}

ExplorationPlan plan_exploration(const MergedMap& merged, const ExplorationOptions& options) {
  std::map<RobotId, Eigen::Vector2d> robots_m;
  for (const auto& [robot, trajectory] : merged.trajectories) {
    if (!trajectory.empty()) robots_m[robot] = trajectory.back().pose.translation();
  }
  std::vector<Eigen::Vector2d> victims_m;
  for (const GlobalObject& o : merged.objects) {
    if (o.class_name == "victim") victims_m.push_back(o.position_m.head<2>());
  }
  return plan_exploration(*merged.grid, robots_m, victims_m, options);
}

}  // namespace cairn::base

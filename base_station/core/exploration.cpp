#include "base_station/core/exploration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base_station/core/merged_map.h"
#include "base_station/core/saliency_layer.h"
#include "common/grid_planning.h"

namespace cairn::base {
namespace {

/// The grid machinery is common/grid_planning.h's: paths only through known free cells (unknown is
/// not traversable) the robot fits in, dearer near walls.
GridPlanningOptions planning_options(const ExplorationOptions& o) {
  GridPlanningOptions p;
  p.free_below = o.free_below;
  p.occupied_above = o.occupied_above;
  p.clearance_m = o.clearance_m;
  p.near_wall_cost = o.near_wall_cost;
  p.inflation_m = o.inflation_m;
  p.unknown_cost = 0.0;
  p.cell_m = o.cell_m;
  return p;
}

/// A robot standing on a cell the map calls unknown or a wall's edge starts from the nearest free
/// cell within this.
constexpr double kStartSearchM = 0.5;

}  // namespace

ExplorationPlan plan_exploration(const OccupancyGrid& grid, const std::map<RobotId, Eigen::Vector2d>& robots_m,
                                 const std::vector<Eigen::Vector2d>& victims_m, const ExplorationOptions& o,
                                 const ExplorationContext& context) {
  ExplorationPlan plan;
  if (grid.width() == 0 || grid.height() == 0) {
    for (const auto& [robot, p] : robots_m) plan.idle.push_back(robot);
    return plan;
  }
  PlanningGrid g(grid, planning_options(o));
  for (const KeepOutArea& area : context.keep_out) g.forbid(in_frame(area, SE2()));  // no path through
  std::vector<FrontierPiece> pieces = frontier_pieces(g);
  // Cells near a goal that failed lately are not offered again, nor cells in a keep-out area.
  for (FrontierPiece& piece : pieces) {
    piece.erase(std::remove_if(piece.begin(), piece.end(),
                               [&](const Eigen::Vector2i& cell) {
                                 const Eigen::Vector2d p = g.centre_m(cell);
                                 return std::any_of(context.blacklist_m.begin(), context.blacklist_m.end(),
                                                    [&](const Eigen::Vector2d& b) {
                                                      return (p - b).norm() < o.blacklist_radius_m;
                                                    }) ||
                                        std::any_of(context.keep_out.begin(), context.keep_out.end(),
                                                    [&](const KeepOutArea& a) { return a.contains(p); });
                               }),
                piece.end());
  }
  // min_frontier_cells counts map cells: a planning cell of cell_m stands for (cell_m / map cell)
  // of them along a frontier.
  const double map_cells_per_cell = g.resolution_m() / grid.resolution_m();
  pieces.erase(
      std::remove_if(pieces.begin(), pieces.end(),
                     [&](const auto& p) { return double(p.size()) * map_cells_per_cell < o.min_frontier_cells; }),
      pieces.end());
  std::sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (const auto& piece : pieces) {
    Frontier f;
    f.cells = int(piece.size());
    f.length_m = f.cells * g.resolution_m();
    Eigen::Vector2d mean(0, 0);
    int near_victim = 0;
    for (const auto& cell : piece) {
      const Eigen::Vector2d p = g.centre_m(cell);
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
      const Eigen::Vector2d p = g.centre_m(cell);
      if ((p - mean).norm() < best) {
        best = (p - mean).norm();
        f.centre_m = p;
      }
    }
    f.weight = 1.0 + o.victim_weight * double(near_victim) / double(piece.size());
    if (context.saliency && o.saliency_weight > 0.0) {
      for (const auto& cell : piece)
        f.saliency = std::max(f.saliency, context.saliency->max_within(g.centre_m(cell), o.saliency_radius_m));
      f.weight *= 1.0 + o.saliency_weight * f.saliency;
    }
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
    const DistanceField field = path_lengths(g, g.cell_of(position), kStartSearchM);
    for (size_t f = 0; f < pieces.size(); ++f) {
      const PieceReach best = nearest_cell_of(pieces[f], g, field);
      if (!std::isfinite(best.path_m)) continue;
      const Frontier& fr = plan.frontiers[f];
      double utility = fr.weight * fr.length_m / (best.path_m + 1.0);
      if (o.coordination == ExplorationOptions::Coordination::kNearestFrontier) utility = 1.0 / (best.path_m + 1.0);
      const auto current = context.current_goals_m.find(robot);
      if (current != context.current_goals_m.end() &&
          std::any_of(pieces[f].begin(), pieces[f].end(),
                      [&](const Eigen::Vector2i& cell) { return (g.centre_m(cell) - current->second).norm() < 1.0; })) {
        utility *= 1.0 + o.hysteresis;  // the frontier it already drives to
      }
      options.push_back({robot, int(f), g.centre_m(best.cell), best.path_m, utility});
    }
  }
  // Greedy: the best (robot, frontier) pair first; then neither that robot nor any frontier goal
  // within the separation of the chosen one is offered again.
  std::sort(options.begin(), options.end(), [](const Option& a, const Option& b) { return a.utility > b.utility; });
  // Uncoordinated, every robot simply takes its best option.
  const bool coordinated = o.coordination == ExplorationOptions::Coordination::kCoordinated;
  std::map<RobotId, bool> assigned;
  for (const Option& opt : options) {
    if (assigned[opt.robot]) continue;
    bool crowded = false;
    for (const ExplorationGoal& goal : plan.goals) {
      crowded = crowded || goal.frontier == opt.frontier || (goal.goal_m - opt.goal_m).norm() < o.separation_m;
    }
    if (crowded && coordinated) continue;
    assigned[opt.robot] = true;
    plan.goals.push_back({opt.robot, opt.frontier, opt.goal_m, opt.path_m, opt.utility});
  }
  if (o.share_when_crowded) {
    for (const Option& opt : options) {  // best first: each robot left over takes its best, shared
      if (assigned[opt.robot]) continue;
      assigned[opt.robot] = true;
      plan.goals.push_back({opt.robot, opt.frontier, opt.goal_m, opt.path_m, opt.utility});
    }
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

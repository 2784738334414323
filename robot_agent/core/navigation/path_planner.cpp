#include "robot_agent/core/navigation/path_planner.h"

#include <cstdio>
#include <optional>

#include "common/grid_planning.h"

namespace cairn::agent {
namespace {

std::string point(const Eigen::Vector2d& p) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "(%.2f, %.2f)", p.x(), p.y());
  return buf;
}

std::string metres(double m) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f m", m);
  return buf;
}

/// The cell the search reached whose centre is nearest to `goal_m`, if within `radius_m`.
std::optional<Eigen::Vector2i> nearest_reached(const PlanningGrid& g, const DistanceField& field,
                                               const Eigen::Vector2d& goal_m, double radius_m) {
  std::optional<Eigen::Vector2i> best;
  double best_m = radius_m;
  for (size_t i = 0; i < g.size(); ++i) {
    if (!field.reached(i)) continue;
    const double d = (g.centre_m(g.cell(i)) - goal_m).norm();
    if (d <= best_m) best_m = d, best = g.cell(i);
  }
  return best;
}

}  // namespace

const char* to_string(PlanStatus status) {
  switch (status) {
    case PlanStatus::kOk:
      return "ok";
    case PlanStatus::kEmptyMap:
      return "empty map";
    case PlanStatus::kStartBlocked:
      return "start blocked";
    case PlanStatus::kGoalBlocked:
      return "goal blocked";
    case PlanStatus::kNoPath:
      return "no path";
    case PlanStatus::kGoalOutsideMap:
      return "goal outside the map";
    case PlanStatus::kGoalKeptOut:
      return "goal in a keep-out area";
  }
  return "?";
}

PathPlanner::PathPlanner(const PathPlannerOptions& options) : options_(options) {}

PlannedPath PathPlanner::plan(const OccupancyGrid& map, const Eigen::Vector2d& from_m, const Eigen::Vector2d& goal_m,
                              double goal_tolerance_m, const std::vector<KeepOutPolygon>& keep_out,
                              double settle_within_m) const {
  const PathPlannerOptions& o = options_;
  GridPlanningOptions gp;
  gp.free_below = o.free_below;
  gp.occupied_above = o.occupied_above;
  gp.cell_m = o.cell_m;
  gp.clearance_m = o.clearance_m;
  gp.near_wall_cost = o.near_wall_cost;
  gp.graded_clearance = true;
  gp.inflation_m = o.robot_radius_m + o.inflation_margin_m;
  gp.unknown_cost = o.unknown_cost;
  gp.margin_m = o.margin_m;
  PlannedPath out;
  out.goal_m = goal_m;
  const Eigen::Vector2d lo = map.origin_m(), hi = lo + map.resolution_m() * Eigen::Vector2d(map.width(), map.height());
  const double outside_m = (goal_m - goal_m.cwiseMax(lo).cwiseMin(hi)).norm();
  if (!goal_m.allFinite() || !from_m.allFinite() || outside_m > o.max_goal_outside_map_m) {
    out.status = PlanStatus::kGoalOutsideMap;
    out.reason = "the goal " + point(goal_m) + " is " + metres(outside_m) + " outside the map (at most " +
                 metres(o.max_goal_outside_map_m) + ")";
    return out;
  }
  for (const KeepOutPolygon& area : keep_out) {
    if (!area.contains(from_m) && area.contains(goal_m)) {
      out.status = PlanStatus::kGoalKeptOut;
      out.reason = "the goal " + point(goal_m) + " lies in the operator's keep-out area " + std::to_string(area.id);
      return out;
    }
  }
  PlanningGrid g(map, gp, {from_m, goal_m});
  if (g.empty()) {
    out.status = PlanStatus::kEmptyMap;
    out.reason = "nothing to plan on";
    return out;
  }
  for (const KeepOutPolygon& area : closed_around(keep_out, from_m, gp.inflation_m)) g.forbid(area);
  Eigen::Vector2i goal = g.cell_of(goal_m);
  if (!g.traversable(g.index(goal))) {
    const std::optional<Eigen::Vector2i> moved = nearest_traversable(g, goal, goal_tolerance_m);
    if (!moved || (g.centre_m(*moved) - goal_m).norm() > goal_tolerance_m) {
      out.status = PlanStatus::kGoalBlocked;
      out.reason = "the goal " + point(goal_m) + " lies within " + metres(gp.inflation_m) +
                   " of a wall (or in unknown space) and no free cell is within " + metres(goal_tolerance_m);
      return out;
    }
    goal = *moved;
    out.goal_m = g.centre_m(goal);
  }
  const Eigen::Vector2i start = g.cell_of(from_m);
  const DistanceField field = path_lengths(g, start, o.start_search_m, goal);
  if (field.start.x() < 0) {
    out.status = PlanStatus::kStartBlocked;
    out.boxed_in = true;
    out.reason = "boxed in: no free cell within " + metres(o.start_search_m) + " of the robot at " + point(from_m);
    return out;
  }
  // No way to the goal: settle for the reachable cell nearest to it, when near enough (the search
  // ran out, so every reachable cell has its length).
  const std::optional<Eigen::Vector2i> settled = field.reached(g.index(goal)) || settle_within_m <= 0
                                                     ? std::nullopt
                                                     : nearest_reached(g, field, goal_m, settle_within_m);
  if (settled) {
    goal = *settled;
    out.goal_m = g.centre_m(goal);
    out.settled = true;
  }
  if (!field.reached(g.index(goal))) {
    out.status = PlanStatus::kNoPath;
    out.reachable_m = field.farthest_m;
    out.boxed_in = field.farthest_m < o.boxed_in_m;
    out.reason = (out.boxed_in ? "boxed in: " : "") + std::string("no path from ") + point(from_m) + " to " +
                 point(out.goal_m) + " (the free space reachable from the robot ends " + metres(field.farthest_m) +
                 " out)";
    return out;
  }
  std::vector<Eigen::Vector2d> cells = extract_path_m(g, field, goal);
  // The robot's own position first (the search may have started from a nearby cell), then the
  // cells; the asked goal itself last when its own cell was planned to.
  out.path_m.reserve(cells.size() + 1);
  out.path_m.push_back(from_m);
  out.path_m.insert(out.path_m.end(), cells.begin() + (field.start == start ? 1 : 0), cells.end());
  if (out.path_m.size() == 1) {
    out.path_m.push_back(out.goal_m);  // already in the goal's cell
  } else if (out.goal_m == goal_m) {
    out.path_m.back() = goal_m;
  }
  out.length_m = field.length_m[g.index(goal)];
  out.status = PlanStatus::kOk;
  return out;
}

}  // namespace cairn::agent

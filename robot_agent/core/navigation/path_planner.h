#pragma once
// Plans the robot's path on its NavMap with common/grid_planning: Dijkstra over 8-connected cells
// of the map (0.1 m; a finer NavMap can be planned on a coarser copy, `cell_m`), cells within the
// robot's radius (plus a margin) of a wall blocked, cells near walls dearer (paths keep to the
// middle of corridors), unknown cells crossed at a cost (a goal beyond what the robot has seen is
// still worth driving towards). A goal cell that is blocked is moved to the nearest traversable
// cell within the goal's tolerance; a start inside the inflated band (the robot brushed a wall, or
// rubble appeared beside it) starts from the nearest traversable cell. The operator's keep-out
// areas (common/keep_out.h, in the robot's frame) are blocked like walls, grown by the same
// inflation (the robot's body keeps out), except one the robot stands in (it drives out of it); a
// goal inside one is refused. Pure.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/keep_out.h"
#include "robot_agent/core/navigation/nav_map.h"

namespace cairn::agent {

struct PathPlannerOptions {
  double robot_radius_m = 0.2;
  /// Added to the radius for the blocked band: at least half a cell's diagonal (0.07 m at 0.1 m),
  /// since a wall may lie anywhere in its cell.
  double inflation_margin_m = 0.08;
  /// Within this of a wall a step costs more, from near_wall_cost at the wall down to 1 (graded).
  double clearance_m = 0.5;
  double near_wall_cost = 3.0;
  double unknown_cost = 3.0;    ///< 0: only known free cells
  double start_search_m = 0.5;  ///< a blocked start cell: the nearest traversable cell within this
  /// A failed search that got no farther than this (straight line from the robot): boxed in.
  double boxed_in_m = 1.0;
  double cell_m = 0.0;    ///< plan on a coarser copy (GridPlanningOptions::cell_m); 0: the map's cells
  double margin_m = 1.0;  ///< unknown space planned beyond the known cells, start and goal
  /// A goal farther than this outside the map's bounds is refused: the planning grid would have to
  /// reach it through unknown space (a goal 5 km off would be 2.5 G cells). The base's goals lie on
  /// the team's map, which other robots may have built far beyond this robot's own: at 15 m, 77
  /// goals were refused in 16 missions on the collapsed floor and the building site, lying 15-27 m
  /// out; a 30 m margin on a 64 m x 40 m site is at most 1.2 M cells at 0.1 m.
  double max_goal_outside_map_m = 30.0;
  double free_below = 0.25;
  double occupied_above = 0.65;
};

enum class PlanStatus { kOk, kEmptyMap, kStartBlocked, kGoalBlocked, kNoPath, kGoalOutsideMap, kGoalKeptOut };

struct PlannedPath {
  PlanStatus status = PlanStatus::kNoPath;
  std::string reason;                   ///< why there is no path (empty when ok)
  std::vector<Eigen::Vector2d> path_m;  ///< the robot's position, then cell centres to the goal
  double length_m = 0;                  ///< weighted length (near-wall and unknown costs included)
  Eigen::Vector2d goal_m{0, 0};         ///< the goal planned to (moved when the asked cell was blocked)
  bool settled = false;                 ///< goal_m is the reachable point nearest an unreachable goal
  /// No path, and the robot cannot get farther than boxed_in_m from where it stands.
  bool boxed_in = false;
  double reachable_m = 0;  ///< how far the failed search got (straight line from the robot)
  bool ok() const { return status == PlanStatus::kOk; }
};

class PathPlanner {
 public:
  explicit PathPlanner(const PathPlannerOptions& options = {});
  /// From `from_m` to `goal_m` (both in the map's frame). The goal counts as reached by any
  /// traversable cell whose centre is within `goal_tolerance_m` of it. With `settle_within_m` > 0,
  /// a goal with no way to it is replaced by the reachable cell nearest to it when that lies within
  /// settle_within_m (PlannedPath::goal_m moved): home, with a teammate parked across the corridor.
  PlannedPath plan(const OccupancyGrid& map, const Eigen::Vector2d& from_m, const Eigen::Vector2d& goal_m,
                   double goal_tolerance_m, const std::vector<KeepOutPolygon>& keep_out = {},
                   double settle_within_m = 0.0) const;
  PlannedPath plan(const NavMap& map, const Eigen::Vector2d& from_m, const Eigen::Vector2d& goal_m,
                   double goal_tolerance_m, const std::vector<KeepOutPolygon>& keep_out = {},
                   double settle_within_m = 0.0) const {
    return plan(map.grid(), from_m, goal_m, goal_tolerance_m, keep_out, settle_within_m);
  }
  const PathPlannerOptions& options() const { return options_; }

 private:
  PathPlannerOptions options_;
};

const char* to_string(PlanStatus status);

}  // namespace cairn::agent

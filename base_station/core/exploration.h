#pragma once
// Where the team should search next. Frontiers of the global map (known free cells next to unknown
// ones, Yamauchi 1997) are grouped into connected pieces; each robot is sent to a different piece
// by a greedy utility over its true path length through known free space (the coordination of
// Burgard et al. 2005, greedy instead of their iterative assignment), and a frontier near a found
// victim counts more: in a collapse, space next to one victim is where others are likeliest (the
// paper's objects of interest steering the search). Pure: a grid and positions in, a plan out.
// The grid machinery (classification, frontiers, Dijkstra) is common/grid_planning.h.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

#include "base_station/core/search_controls.h"
#include "common/ids.h"
#include "common/occupancy_grid.h"

namespace cairn::base {
class SaliencyLayer;
}

namespace cairn::base {

struct ExplorationOptions {
  double free_below = 0.25;      ///< a known cell below this occupancy probability is free
  double occupied_above = 0.65;  ///< above it, a wall
  int min_frontier_cells = 15;   ///< smaller pieces are noise (0.75 m of frontier at 5 cm cells)
  double clearance_m = 0.25;     ///< paths within this of a wall cost `near_wall_cost` times more
  double near_wall_cost = 4.0;
  double victim_radius_m = 6.0;  ///< frontier cells this close to a victim weigh 1 + victim_weight
  double victim_weight = 2.0;
  /// Attentive exploration (the paper's saliency map, ExplorationContext::saliency): a frontier's
  /// weight is multiplied by 1 + saliency_weight x the strongest saliency within saliency_radius_m
  /// of its cells, so a salient opening is searched first. 0: the layer is ignored.
  double saliency_weight = 0.0;
  double saliency_radius_m = 3.0;
  double separation_m = 4.0;  ///< no two robots get goals closer than this
  /// kCoordinated: the greedy allocation above (Burgard et al. 2005). kNearestFrontier: every robot
  /// takes its own nearest frontier, whatever the others do (explore_lite's behaviour, for
  /// comparison).
  enum class Coordination { kCoordinated, kNearestFrontier } coordination = Coordination::kCoordinated;
  /// A robot left without a goal by the separation rule still gets its best frontier, shared: no
  /// robot stands idle while a frontier it can reach remains.
  bool share_when_crowded = true;
  /// The frontier a robot is already driving to counts this much more (1 + hysteresis): a new plan
  /// does not swap goals back and forth between nearly equal frontiers.
  double hysteresis = 0.5;
  double blacklist_radius_m = 1.0;  ///< frontier cells this close to a blacklisted goal are skipped
  /// Paths keep the robot's centre this far from walls (its radius and a margin): a frontier
  /// behind a gap no robot fits through is not reachable.
  double inflation_m = 0.25;
  /// Planning cells (m): the map's 0.05 m cells are merged 2 x 2; a 64 m x 40 m map is then 0.26 M
  /// cells per Dijkstra.
  double cell_m = 0.1;
};

/// What the base knows beyond the map when it plans (GoalAllocator).
struct ExplorationContext {
  std::vector<Eigen::Vector2d> blacklist_m;            ///< goals that failed lately
  std::map<RobotId, Eigen::Vector2d> current_goals_m;  ///< the goals being driven
  const SaliencyLayer* saliency = nullptr;             ///< the merged saliency layer, if any
  std::vector<KeepOutArea> keep_out;                   ///< the operator's: no goal in them, no path through them
};

struct Frontier {
  Eigen::Vector2d centre_m{0, 0};  ///< the piece's cell nearest its centroid
  int cells = 0;
  double length_m = 0;  ///< cells x resolution
  double weight = 1;    ///< (1 + victim_weight x fraction of cells near a victim) x (1 + saliency_weight x saliency)
  double saliency = 0;  ///< the strongest saliency within saliency_radius_m of its cells, 0..1
};

struct ExplorationGoal {
  RobotId robot;
  int frontier = -1;             ///< index into ExplorationPlan::frontiers
  Eigen::Vector2d goal_m{0, 0};  ///< the frontier's cell nearest to the robot along free space
  double path_m = 0;             ///< path length there through known free cells
  double utility = 0;            ///< weight x length / (path + 1 m)
};

/// A robot driving toward a teammate instead of exploring (active_linking.h), as shown and exported.
struct MeetingGoal {
  RobotId robot;
  RobotId teammate;        ///< the robot it is to meet
  Eigen::Vector2d goal_m;  ///< where it drives, global frame (under the hypothesis if not placed yet)
};

struct ExplorationPlan {
  std::vector<Frontier> frontiers;     ///< largest first
  std::vector<ExplorationGoal> goals;  ///< at most one per robot, best first
  std::vector<RobotId> idle;           ///< robots with no reachable frontier left (or none for them)
  std::vector<MeetingGoal> meetings;   ///< robots sent to meet a teammate (set by the caller)
  /// The saliency layer the base had when it planned (drawn on the map; set by the caller).
  std::shared_ptr<const SaliencyLayer> saliency;
};

ExplorationPlan plan_exploration(const OccupancyGrid& grid, const std::map<RobotId, Eigen::Vector2d>& robots_m,
                                 const std::vector<Eigen::Vector2d>& victims_m, const ExplorationOptions& options = {},
                                 const ExplorationContext& context = {});

struct MergedMap;
/// The plan for the merged global map, its linked robots at their newest keyframes and the
/// victims found so far.
ExplorationPlan plan_exploration(const MergedMap& merged, const ExplorationOptions& options = {});

}  // namespace cairn::base

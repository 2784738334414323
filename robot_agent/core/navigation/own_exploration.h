#pragma once
// Exploration for a robot out of contact with its base (no goals arrive): the nearest frontier of
// its own NavMap it can reach through known free space (common/grid_planning: frontier pieces,
// Dijkstra with the robot's radius inflated), skipping frontier cells near goals that already
// failed (unreachable or stuck). Nearest first is Yamauchi's (1997) frontier exploration for one
// robot. The operator's keep-out areas (in the robot's frame) are neither crossed nor explored,
// except one the robot stands in. Pure.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "common/keep_out.h"
#include "robot_agent/core/navigation/nav_map.h"

namespace cairn::agent {

struct OwnExplorationOptions {
  double robot_radius_m = 0.2;
  double inflation_margin_m = 0.08;  ///< as NavigatorOptions::inflation_margin_m
  double clearance_m = 0.5;          ///< as the planner: paths near walls cost more
  double near_wall_cost = 3.0;
  double min_frontier_m = 0.5;      ///< pieces shorter than this (cells x resolution) are noise
  double min_path_m = 0.5;          ///< frontier cells nearer than this are where the robot stands
  double blacklist_radius_m = 1.0;  ///< frontier cells this close to a failed goal are skipped
  double start_search_m = 0.5;      ///< a robot on a blocked cell starts from the nearest free one
};

struct OwnFrontierGoal {
  Eigen::Vector2d goal_m{0, 0};  ///< the frontier cell (local frame)
  double path_m = 0;             ///< weighted path length there through known free space
  double frontier_length_m = 0;  ///< the length of its frontier piece
};

/// The nearest reachable frontier cell of `map` from `robot_m` not within blacklist_radius_m of a
/// `blacklist_m` position nor in a `keep_out` area; nullopt when none is left.
std::optional<OwnFrontierGoal> nearest_own_frontier(const OccupancyGrid& map, const Eigen::Vector2d& robot_m,
                                                    const std::vector<Eigen::Vector2d>& blacklist_m,
                                                    const OwnExplorationOptions& options = {},
                                                    const std::vector<KeepOutPolygon>& keep_out = {});

/// nearest_own_frontier with the blacklist kept: the agent blacklists each own-frontier goal that
/// ended unreachable or stuck.
class OwnExploration {
 public:
  explicit OwnExploration(const OwnExplorationOptions& options = {}) : options_(options) {}
  std::optional<OwnFrontierGoal> next_goal(const NavMap& map, const Eigen::Vector2d& robot_m) const {
    return nearest_own_frontier(map.grid(), robot_m, blacklist_, options_);
  }
  void blacklist(const Eigen::Vector2d& goal_m) { blacklist_.push_back(goal_m); }
  const std::vector<Eigen::Vector2d>& blacklisted() const { return blacklist_; }
  void clear_blacklist() { blacklist_.clear(); }

 private:
  OwnExplorationOptions options_;
  std::vector<Eigen::Vector2d> blacklist_;
};

}  // namespace cairn::agent

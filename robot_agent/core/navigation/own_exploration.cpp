#include "robot_agent/core/navigation/own_exploration.h"

#include <algorithm>
#include <cmath>

#include "common/grid_planning.h"

namespace cairn::agent {

std::optional<OwnFrontierGoal> nearest_own_frontier(const OccupancyGrid& map, const Eigen::Vector2d& robot_m,
                                                    const std::vector<Eigen::Vector2d>& blacklist_m,
                                                    const OwnExplorationOptions& o,
                                                    const std::vector<KeepOutPolygon>& keep_out) {
  GridPlanningOptions gp;
  gp.clearance_m = o.clearance_m;
  gp.near_wall_cost = o.near_wall_cost;
  gp.graded_clearance = true;
  gp.inflation_m = o.robot_radius_m + o.inflation_margin_m;
  gp.unknown_cost = 0.0;  // reachable means through space the robot has seen free
  PlanningGrid g(map, gp);
  if (g.empty()) return std::nullopt;
  const std::vector<KeepOutPolygon> closed = closed_around(keep_out, robot_m, gp.inflation_m);
  for (const KeepOutPolygon& area : closed) g.forbid(area);
  const std::vector<FrontierPiece> pieces = frontier_pieces(g);
  const DistanceField field = path_lengths(g, g.cell_of(robot_m), o.start_search_m);
  NearestFrontierOptions nf;
  nf.min_piece_cells = std::max(1, int(std::ceil(o.min_frontier_m / g.resolution_m() - 1e-9)));
  nf.min_path_m = o.min_path_m;
  const double r2 = o.blacklist_radius_m * o.blacklist_radius_m;
  auto blacklisted = [&](const Eigen::Vector2d& p) {
    for (const Eigen::Vector2d& b : blacklist_m) {
      if ((p - b).squaredNorm() <= r2) return true;
    }
    for (const KeepOutPolygon& area : closed) {
      if (area.contains(p)) return true;
    }
    return false;
  };
  const std::optional<FrontierTarget> target = nearest_frontier(g, field, pieces, nf, blacklisted);
  if (!target) return std::nullopt;
  return OwnFrontierGoal{target->position_m, target->path_m,
                         double(pieces[size_t(target->piece)].size()) * g.resolution_m()};
}

}  // namespace cairn::agent

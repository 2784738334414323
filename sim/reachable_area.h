#pragma once
// The area a team could explore: the floor plan's free cells within view_m of a place a robot (a
// disc of robot_radius_m) can drive to from where the robots entered. The denominator of the
// exploration coverage (tools/eval): space behind a gap no robot fits through, sealed pockets in
// the rubble and what lies off the map cannot be explored by anyone, so they do not count.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sim/floor_plan.h"

namespace cairn::sim {

struct ReachableAreaOptions {
  double robot_radius_m = 0.2;
  double view_m = 1.5;  ///< free cells this close to a drivable place count (seen from up close)
};

/// Row-major like FloorPlan (row 0 at the bottom): 1 = explorable free cell. Starts where the
/// robot does not fit, or off the map, are ignored.
std::vector<uint8_t> reachable_free_cells(const FloorPlan& plan, const std::vector<Eigen::Vector2d>& starts_m,
                                          const ReachableAreaOptions& options = {});

}  // namespace cairn::sim

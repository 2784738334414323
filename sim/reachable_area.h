#pragma once
// The area a team could explore: the floor plan's free cells connected (4-neighbours, through free
// cells on the map) to where the robots entered. The denominator of the exploration coverage
// (tools/eval): what lies beyond the map's edge or in sealed pockets cannot be explored by anyone.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sim/floor_plan.h"

namespace cairn::sim {

/// Row-major like FloorPlan (row 0 at the bottom): 1 = reachable free cell, 0 = wall, sealed or
/// off the map. Starts on a wall or off the map are ignored.
std::vector<uint8_t> reachable_free_cells(const FloorPlan& plan, const std::vector<Eigen::Vector2d>& starts_m);

}  // namespace cairn::sim

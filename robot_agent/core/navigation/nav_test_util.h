#pragma once
// Test helpers for the navigation core: grids drawn in metres, small worlds of wall segments
// (ray-cast by robot_agent/core/test_util.h), and a closed loop that drives a Navigator through a
// world with a unicycle integration (perfect SLAM: the navigator gets the true pose).
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "common/grid_drawing_test_util.h"
#include "common/occupancy_grid.h"
#include "robot_agent/core/navigation/navigator.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent::testing {

using cairn::testing::GridDrawing;  // common/grid_drawing_test_util.h

/// Walls of the axis-aligned box [x0, x1] x [y0, y1].
void add_box(std::vector<Segment>* world, double x0, double y0, double x1, double y1);
/// A polygon of `sides` segments round a circle (rubble round the robot).
void add_ring(std::vector<Segment>* world, const Eigen::Vector2d& centre, double radius_m, int sides = 24);
/// Distance from p to the nearest wall segment.
double distance_to_walls(const std::vector<Segment>& world, const Eigen::Vector2d& p);

/// A 4 m x 4 m room [0, 4]^2 with a 1 m door (y 1.5-2.5) in its east wall into a 1.5 m wide
/// corridor (y 1.25-2.75) running east to x = 10, where it turns north (x 8.5-10) up to y = 7.
std::vector<Segment> room_and_corridor();

/// One step of a unicycle: turn and move on the arc for dt.
SE2 unicycle_step(const SE2& pose, const VelocityCommand& command, double dt_s);

struct DriveOptions {
  double dt_s = 0.1;    ///< one scan per step
  double max_s = 60;    ///< gives up after this much message time
  bool frozen = false;  ///< the wheels spin but the robot does not move (stuck in rubble)
  int num_beams = 360;
};

struct DriveResult {
  double seconds = 0;  ///< message time driven
  double min_wall_distance_m = 1e9;
  double travelled_m = 0;
  double max_linear_mps = 0;
  int steps = 0;
};

/// Updates `nav` with scans of `world` at `*pose` every dt, moving `*pose` by the commands, until
/// the navigator stops driving (or max_s, or `until` says so). `*stamp_ns` advances.
DriveResult drive(Navigator* nav, const std::vector<Segment>& world, SE2* pose, StampNs* stamp_ns,
                  const DriveOptions& options = {}, const std::function<bool()>& until = {});

}  // namespace cairn::agent::testing

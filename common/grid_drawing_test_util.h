#pragma once
// Test helper: an all-unknown occupancy grid of width_m x height_m on which tests paint free space
// and walls as rectangles in metres (grid planning, exploration, navigation tests).
#include <Eigen/Core>

#include "common/occupancy_grid.h"

namespace cairn::testing {

struct GridDrawing {
  OccupancyGrid grid;
  explicit GridDrawing(double width_m = 10, double height_m = 6, double resolution_m = 0.1)
      : grid(options(resolution_m), {0, 0}, {width_m, height_m}) {}
  static OccupancyGridOptions options(double resolution_m) {
    OccupancyGridOptions o;
    o.resolution_m = resolution_m;
    return o;
  }
  /// Sets every cell whose centre lies in [x0, x1) x [y0, y1) to `log_odds`.
  void paint(double x0, double y0, double x1, double y1, float log_odds) {
    for (int r = 0; r < grid.height(); ++r) {
      for (int c = 0; c < grid.width(); ++c) {
        const Eigen::Vector2d p = grid.cell_center_m(c, r);
        if (p.x() >= x0 && p.x() < x1 && p.y() >= y0 && p.y() < y1) {
          grid.update_cell(c, r, log_odds - grid.log_odds(c, r));
        }
      }
    }
  }
  void free(double x0, double y0, double x1, double y1) { paint(x0, y0, x1, y1, -2.f); }
  void wall(double x0, double y0, double x1, double y1) { paint(x0, y0, x1, y1, 2.f); }
  /// A closed room [1, 9] x [1, 5], walls 0.1 m thick outside it.
  void room() {
    free(1, 1, 9, 5);
    wall(0.9, 0.9, 9.1, 1);
    wall(0.9, 5, 9.1, 5.1);
    wall(0.9, 0.9, 1, 5.1);
    wall(9, 0.9, 9.1, 5.1);
  }
};

}  // namespace cairn::testing

#pragma once
// Test helper: the simulator tests' floor plan, a 10 m x 6 m room at 0.05 m (walls one cell thick:
// inner faces at x = 0.05, 9.95, y = 0.05, 5.95) with a pillar at x 5..5.5, y 2.5..3.5.
#include <cstdint>
#include <vector>

#include "sim/floor_plan.h"

namespace cairn::sim::testing {

inline FloorPlan room_with_pillar() {
  const int w = 200, h = 120;
  std::vector<uint8_t> cells(size_t(w) * h, 0);
  for (int c = 0; c < w; ++c) cells[c] = cells[size_t(h - 1) * w + c] = 1;
  for (int r = 0; r < h; ++r) cells[size_t(r) * w] = cells[size_t(r) * w + w - 1] = 1;
  for (int r = 50; r < 70; ++r)
    for (int c = 100; c < 110; ++c) cells[size_t(r) * w + c] = 1;
  return FloorPlan(w, h, 0.05, Eigen::Vector2d(0, 0), cells);
}

}  // namespace cairn::sim::testing

#include "sim/reachable_area.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::sim {
namespace {

constexpr double kRes = 0.1;

// 10 m x 6 m at 0.1 m: a wall at x = 5 m splits it; a door in it of `door_m`; a sealed 1 m box in
// the right room at (8, 4).
FloorPlan two_rooms(double door_m) {
  const int w = 100, h = 60;
  std::vector<uint8_t> walls(size_t(w) * h, 0);
  auto set = [&](double x0, double y0, double x1, double y1, uint8_t v) {
    for (int r = int(std::lround(y0 / kRes)); r < int(std::lround(y1 / kRes)); ++r)
      for (int c = int(std::lround(x0 / kRes)); c < int(std::lround(x1 / kRes)); ++c) walls[size_t(r) * w + c] = v;
  };
  set(0, 0, 10, 0.1, 1), set(0, 5.9, 10, 6, 1), set(0, 0, 0.1, 6, 1), set(9.9, 0, 10, 6, 1);
  set(5.0, 0, 5.1, 6, 1);
  if (door_m > 0) set(5.0, 2.0, 5.1, 2.0 + door_m, 0);
  set(7.5, 3.5, 8.5, 4.5, 1), set(7.6, 3.6, 8.4, 4.4, 0);  // a hollow box: its inside is sealed
  return FloorPlan(w, h, kRes, Eigen::Vector2d::Zero(), walls);
}

double area_m2(const std::vector<uint8_t>& v) {
  int n = 0;
  for (uint8_t x : v) n += x;
  return n * kRes * kRes;
}

TEST(ReachableArea, FreeSpaceARobotCanSeeFromUpCloseCounts) {
  const double left_room = 4.9 * 5.8;  // x in [0.1, 5.0), y in [0.1, 5.9)
  EXPECT_NEAR(area_m2(reachable_free_cells(two_rooms(0.0), {{1.5, 1.5}})), left_room, 0.05) << "the left room only";
  const auto both = reachable_free_cells(two_rooms(1.0), {{1.5, 1.5}});
  const double right_room = 4.8 * 5.8 - 1.0;  // minus the box (walls and sealed inside)
  EXPECT_NEAR(area_m2(both), left_room + right_room + 0.1, 0.1);
  EXPECT_EQ(both[size_t(40) * 100 + 80], 0) << "inside the sealed box";
  // A 0.3 m gap: the robot (0.4 m wide) does not fit; it sees view_m into the right room only.
  const double through_gap = area_m2(reachable_free_cells(two_rooms(0.3), {{1.5, 1.5}}));
  EXPECT_GT(through_gap, left_room + 0.5);
  EXPECT_LT(through_gap, left_room + 5.0);
  EXPECT_EQ(area_m2(reachable_free_cells(two_rooms(1.0), {{5.05, 1.5}, {50, 50}})), 0.0)
      << "a start on a wall or off the map";
}

}  // namespace
}  // namespace cairn::sim

#include "sim/reachable_area.h"

#include <gtest/gtest.h>

namespace cairn::sim {
namespace {

// 10 x 6 cells of 1 m: a wall at column 5 splits the map, with a sealed 1-cell pocket at (8, 4).
FloorPlan two_rooms(bool door) {
  std::vector<uint8_t> walls(60, 0);
  for (int r = 0; r < 6; ++r) walls[size_t(r) * 10 + 5] = 1;
  if (door) walls[size_t(2) * 10 + 5] = 0;
  for (int c = 7; c <= 9; ++c) walls[size_t(3) * 10 + c] = walls[size_t(5) * 10 + c] = 1;
  walls[size_t(4) * 10 + 7] = walls[size_t(4) * 10 + 9] = 1;
  return FloorPlan(10, 6, 1.0, Eigen::Vector2d::Zero(), walls);
}

int count(const std::vector<uint8_t>& v) {
  int n = 0;
  for (uint8_t x : v) n += x;
  return n;
}

TEST(ReachableArea, OnlyTheFreeCellsConnectedToAStartCount) {
  EXPECT_EQ(count(reachable_free_cells(two_rooms(false), {{1.5, 1.5}})), 30) << "the left room only";
  // Through the door: both rooms (30 + the door + 15), not the walls nor the sealed pocket.
  const auto both = reachable_free_cells(two_rooms(true), {{1.5, 1.5}});
  EXPECT_EQ(count(both), 46);
  EXPECT_EQ(both[size_t(4) * 10 + 8], 0) << "the sealed pocket";
  EXPECT_EQ(count(reachable_free_cells(two_rooms(false), {{1.5, 1.5}, {8.5, 0.5}})), 30 + 15);
  EXPECT_EQ(count(reachable_free_cells(two_rooms(false), {{5.5, 1.5}, {50, 50}})), 0)
      << "a start on a wall or off the map";
}

}  // namespace
}  // namespace cairn::sim

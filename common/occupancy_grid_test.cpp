#include "common/occupancy_grid.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace cairn {
namespace {

TEST(OccupancyGrid, RayCastMarksFreeThenHit) {
  OccupancyGrid grid;
  grid.insert_scan(SE2(0, 0, 0), {Eigen::Vector2f(2.0f, 0.0f)});
  const auto hit = grid.cell_of({2.0, 0.0});
  const auto free = grid.cell_of({1.0, 0.0});
  EXPECT_GT(grid.probability(hit.x(), hit.y()), 0.6);
  EXPECT_LT(grid.probability(free.x(), free.y()), 0.45);
  const auto unknown = grid.cell_of({1.0, 1.0});
  EXPECT_FALSE(grid.known(unknown.x(), unknown.y()));
}

TEST(OccupancyGrid, ALineIsClearUnlessAnOccupiedCellLiesOnIt) {
  OccupancyGrid grid;
  // A scan from the origin with one return 3 m east: free cells up to a wall cell there.
  for (int i = 0; i < 3; ++i) grid.insert_scan(SE2(), {Eigen::Vector2f(3, 0)});
  EXPECT_TRUE(grid.line_clear({0, 0}, {2.5, 0}));
  EXPECT_FALSE(grid.line_clear({0, 0}, {4, 0})) << "the wall at 3 m";
  EXPECT_FALSE(grid.line_clear({4, 0}, {0, 0})) << "either way";
  EXPECT_TRUE(grid.line_clear({0, 1}, {4, 1})) << "a line north of it (unknown cells do not block)";
  EXPECT_TRUE(grid.line_clear({50, 50}, {60, 60})) << "outside the grid";
}

TEST(OccupancyGrid, GrowsInEveryDirectionKeepingContent) {
  OccupancyGrid grid;
  grid.insert_scan(SE2(0, 0, 0), {Eigen::Vector2f(1.0f, 0.0f)});
  const double area_before = grid.known_area_m2();
  grid.insert_scan(SE2(-20, -20, 0), {Eigen::Vector2f(-1.0f, 0.0f)});
  grid.insert_scan(SE2(20, 20, 0), {Eigen::Vector2f(1.0f, 0.0f)});
  const auto hit = grid.cell_of({1.0, 0.0});
  EXPECT_GT(grid.probability(hit.x(), hit.y()), 0.6);
  EXPECT_GT(grid.known_area_m2(), area_before);
  EXPECT_GE(grid.width() * grid.resolution_m(), 40.0);
}

TEST(OccupancyGrid, WritesMapServerPgmAndYaml) {
  OccupancyGrid grid;
  grid.insert_scan(SE2(0, 0, 0), {Eigen::Vector2f(1.0f, 0.5f), Eigen::Vector2f(1.0f, -0.5f)});
  const std::string stem = ::testing::TempDir() + "/grid_test_map";
  ASSERT_TRUE(grid.write_pgm_yaml(stem));
  std::ifstream pgm(stem + ".pgm", std::ios::binary);
  std::string magic;
  pgm >> magic;
  EXPECT_EQ(magic, "P5");
  std::ifstream yaml(stem + ".yaml");
  std::string first;
  std::getline(yaml, first);
  EXPECT_EQ(first, "image: grid_test_map.pgm");
  EXPECT_FALSE(grid.write_pgm_yaml("/nonexistent-dir/x"));
}

}  // namespace
}  // namespace cairn

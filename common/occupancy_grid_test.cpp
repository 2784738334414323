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

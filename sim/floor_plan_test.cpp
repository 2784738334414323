#include "sim/floor_plan.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::sim {
namespace {

// 5 m x 5 m at 0.05 m with one wall column at x = [3.0, 3.05).
FloorPlan wall_at_x3() {
  std::vector<uint8_t> cells(100 * 100, 0);
  for (int r = 0; r < 100; ++r) cells[size_t(r) * 100 + 60] = 1;
  return FloorPlan(100, 100, 0.05, Eigen::Vector2d(0, 0), cells);
}

TEST(FloorPlan, RayHitsKnownWallDistance) {
  const FloorPlan plan = wall_at_x3();
  const RayHit hit = plan.cast_ray(Eigen::Vector2d(1.0, 2.5), 0.0, 10.0);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.range_m, 2.0, 1e-9);
  EXPECT_TRUE(hit.x_face);
  const double a = 0.5;
  const RayHit oblique = plan.cast_ray(Eigen::Vector2d(1.0, 1.0), a, 10.0);
  ASSERT_TRUE(oblique.hit);
  EXPECT_NEAR(oblique.range_m, 2.0 / std::cos(a), 1e-9);
}

TEST(FloorPlan, RayWithoutWallOrBeyondRangeHasNoReturn) {
  const FloorPlan plan = wall_at_x3();
  EXPECT_FALSE(plan.cast_ray(Eigen::Vector2d(1.0, 2.5), M_PI, 10.0).hit);  // leaves the map
  EXPECT_FALSE(plan.cast_ray(Eigen::Vector2d(1.0, 2.5), 0.0, 1.5).hit);    // wall at 2 m
  EXPECT_FALSE(plan.cast_ray(Eigen::Vector2d(1.0, 2.5), M_PI / 2, 10.0).hit);
}

TEST(FloorPlan, ClearanceChecks) {
  const FloorPlan plan = wall_at_x3();
  EXPECT_TRUE(plan.disc_free(Eigen::Vector2d(2.5, 2.5), 0.2));
  EXPECT_FALSE(plan.disc_free(Eigen::Vector2d(2.85, 2.5), 0.2));
  EXPECT_FALSE(plan.disc_free(Eigen::Vector2d(0.1, 2.5), 0.2));  // off the map
  EXPECT_TRUE(plan.segment_free(Eigen::Vector2d(1, 1), Eigen::Vector2d(2.7, 4), 0.2));
  EXPECT_FALSE(plan.segment_free(Eigen::Vector2d(1, 1), Eigen::Vector2d(4, 1), 0.2));
  EXPECT_TRUE(plan.wall_at(Eigen::Vector2d(3.02, 0.5)));
}

}  // namespace
}  // namespace cairn::sim

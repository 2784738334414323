#include "common/odometry_noise.h"

#include <gtest/gtest.h>

namespace cairn {
namespace {

std::vector<SE2> straight_line(int n, double step_m) {
  std::vector<SE2> poses;
  for (int i = 0; i < n; ++i) poses.emplace_back(i * step_m, 0.0, 0.0);
  return poses;
}

TEST(OdometryNoise, SeededAndDeterministic) {
  const auto truth = straight_line(200, 0.1);
  const auto a = add_odometry_noise(truth, {0.1, 0.05, 0.0, 7});
  const auto b = add_odometry_noise(truth, {0.1, 0.05, 0.0, 7});
  const auto c = add_odometry_noise(truth, {0.1, 0.05, 0.0, 8});
  ASSERT_EQ(a.size(), truth.size());
  EXPECT_EQ(a.back().x(), b.back().x());
  EXPECT_NE(a.back().x(), c.back().x());
  EXPECT_EQ(a.front().x(), truth.front().x());
}

TEST(OdometryNoise, ZeroNoiseReproducesTheInput) {
  const auto truth = straight_line(50, 0.2);
  const auto out = add_odometry_noise(truth, {0.0, 0.0, 0.0, 1});
  EXPECT_NEAR(out.back().x(), truth.back().x(), 1e-9);
  EXPECT_NEAR(out.back().y(), 0.0, 1e-9);
}

TEST(OdometryNoise, DriftGrowsWithDistance) {
  // Mean final yaw error over many seeds grows with the distance travelled (no motion, no drift).
  double err_short = 0, err_long = 0;
  for (uint32_t seed = 1; seed <= 50; ++seed) {
    err_short += std::abs(add_odometry_noise(straight_line(21, 0.1), {0.1, 0.05, 0.0, seed}).back().yaw());
    err_long += std::abs(add_odometry_noise(straight_line(201, 0.1), {0.1, 0.05, 0.0, seed}).back().yaw());
  }
  EXPECT_GT(err_long, 2.0 * err_short);
  const auto still = add_odometry_noise(std::vector<SE2>(10, SE2(1, 2, 0.3)), {0.1, 0.05, 0.0, 3});
  EXPECT_NEAR(still.back().x(), 1.0, 1e-12);
  EXPECT_NEAR(still.back().yaw(), 0.3, 1e-12);
}

}  // namespace
}  // namespace cairn

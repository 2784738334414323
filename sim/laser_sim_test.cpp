#include "sim/laser_sim.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::sim {
namespace {

// A 6 m x 4 m box room (walls one cell thick) at 0.05 m.
FloorPlan box_room() {
  const int w = 120, h = 80;
  std::vector<uint8_t> cells(size_t(w) * h, 0);
  for (int c = 0; c < w; ++c) cells[c] = cells[size_t(h - 1) * w + c] = 1;
  for (int r = 0; r < h; ++r) cells[size_t(r) * w] = cells[size_t(r) * w + w - 1] = 1;
  return FloorPlan(w, h, 0.05, Eigen::Vector2d(0, 0), cells);
}

TEST(LaserSimulator, RangesMatchRoomGeometry) {
  LaserOptions options;
  options.noise_sd_m = 0.0;
  const LaserSimulator laser(options);
  std::mt19937_64 rng(1);
  const LaserScan scan = laser.scan(box_room(), SE2(2.0, 1.0, 0.0), 5, rng);
  ASSERT_EQ(scan.ranges_m.size(), 360u);
  EXPECT_EQ(scan.stamp_ns, 5);
  EXPECT_NEAR(scan.angle_min_rad, -M_PI, 1e-6);
  EXPECT_NEAR(scan.angle_increment_rad, 2 * M_PI / 360, 1e-7);
  // Beam 180 looks forward (+x): inner face of the east wall at x = 5.95.
  EXPECT_NEAR(scan.ranges_m[180], 3.95, 1e-4);
  EXPECT_NEAR(scan.ranges_m[270], 2.95, 1e-4);  // +y: north wall inner face at y = 3.95
  EXPECT_NEAR(scan.ranges_m[90], 0.95, 1e-4);   // -y
  EXPECT_NEAR(scan.ranges_m[0], 1.95, 1e-4);    // -x
}

TEST(LaserSimulator, NoiseAndMaxRange) {
  LaserOptions options;
  options.noise_sd_m = 0.05;
  options.max_range_m = 3.0;
  const LaserSimulator laser(options);
  std::mt19937_64 rng(1);
  const SE2 facing_north(2.0, 1.0, M_PI / 2);
  double sum = 0, sum_sq = 0;
  const int n = 300;
  for (int k = 0; k < n; ++k) {
    const LaserScan s = laser.scan(box_room(), facing_north, 0, rng);
    EXPECT_TRUE(std::isinf(s.ranges_m[90]));  // sensor -pi/2 = world +x: wall at 3.95 m > max
    const double r = s.ranges_m[180];         // forward = world +y: wall at 2.95 m
    sum += r;
    sum_sq += (r - 2.95) * (r - 2.95);
  }
  EXPECT_NEAR(sum / n, 2.95, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.05, 0.008);
}

TEST(LaserSimulator, PartialFieldOfView) {
  LaserOptions options;
  options.fov_deg = 180.0;
  options.beams = 181;
  options.noise_sd_m = 0.0;
  const LaserSimulator laser(options);
  std::mt19937_64 rng(1);
  const LaserScan s = laser.scan(box_room(), SE2(2.0, 1.0, 0.0), 0, rng);
  EXPECT_NEAR(s.angle_min_rad, -M_PI / 2, 1e-6);
  EXPECT_NEAR(beam_angle_rad(s, 180), M_PI / 2, 1e-5);
  EXPECT_NEAR(s.ranges_m[90], 3.95, 1e-4);
}

}  // namespace
}  // namespace cairn::sim

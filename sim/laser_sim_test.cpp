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

TEST(LaserSimulator, OtherRobotsAreCirclesNearerThanTheWalls) {
  LaserOptions options;
  options.noise_sd_m = 0.0;
  const LaserSimulator laser(options);
  std::mt19937_64 rng(1);
  // A robot of radius 0.2 m 2 m ahead (+x), one behind a wall (outside the room), one beyond range.
  const std::vector<Eigen::Vector2d> others = {{4.0, 1.0}, {8.0, 1.0}, {2.0, 30.0}};
  const LaserScan s = laser.scan(box_room(), SE2(2.0, 1.0, 0.0), 0, rng, others, 0.2);
  EXPECT_NEAR(s.ranges_m[180], 1.8, 1e-4);        // the near face of the circle
  EXPECT_NEAR(s.ranges_m[270], 2.95, 1e-4);       // +y: the wall, as without robots
  EXPECT_NEAR(s.ranges_m[0], 1.95, 1e-4);         // -x: the wall
  const double off_axis = std::atan2(0.15, 2.0);  // a chord 0.15 m off the centre line
  const int beam = 180 + int(std::floor(off_axis / (M_PI / 180)));
  const double a = beam_angle_rad(s, beam);
  const double b = 2.0 * std::cos(a), expected = b - std::sqrt(b * b - (4.0 - 0.04));
  EXPECT_NEAR(s.ranges_m[size_t(beam)], expected, 1e-4);                // exact ray-circle intersection
  EXPECT_NEAR(s.ranges_m[186], 3.95 / std::cos(6 * M_PI / 180), 1e-3);  // misses the circle: the east wall
  // The teammate's reflective tape comes back bright, the walls dull.
  ASSERT_EQ(s.intensities.size(), s.ranges_m.size());
  EXPECT_FLOAT_EQ(s.intensities[180], options.teammate_intensity);
  EXPECT_FLOAT_EQ(s.intensities[size_t(beam)], options.teammate_intensity);
  EXPECT_FLOAT_EQ(s.intensities[186], options.surface_intensity);
  EXPECT_FLOAT_EQ(s.intensities[270], options.surface_intensity);
  // The robot's own position is never passed: no robot, same scan as before the feature.
  std::mt19937_64 rng_a(3), rng_b(3);
  EXPECT_EQ(laser.scan(box_room(), SE2(2.0, 1.0, 0.3), 0, rng_a).ranges_m,
            laser.scan(box_room(), SE2(2.0, 1.0, 0.3), 0, rng_b, {}, 0.2).ranges_m);
}

}  // namespace
}  // namespace cairn::sim

#include "common/laser_scan.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn {
namespace {

TEST(LaserScan, FiltersAndCountsBadReadings) {
  LaserScan s;
  s.angle_min_rad = 0.f;
  s.angle_increment_rad = float(M_PI / 2);
  s.range_min_m = 0.1f;
  s.range_max_m = 10.f;
  s.ranges_m = {1.f, std::nanf(""), -INFINITY, 0.f, 10.f, 2.f, INFINITY};
  ScanFilterStats stats;
  const auto pts = scan_to_points(s, &stats);
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_NEAR(pts[0].x(), 1.f, 1e-6);
  EXPECT_NEAR(pts[1].x(), 0.f, 1e-5);  // beam 5 at 450 deg = 90 deg
  EXPECT_NEAR(pts[1].y(), 2.f, 1e-5);
  EXPECT_EQ(stats.valid, 2);
  EXPECT_EQ(stats.nan_or_inf, 2);
  EXPECT_EQ(stats.too_close, 1);
  EXPECT_EQ(stats.max_range, 2);  // 10 m = range_max and +inf: no return
}

TEST(VoxelFilter2d, KeepsTheFirstPointOfEachCellInScanOrder) {
  const std::vector<Eigen::Vector2f> points = {{0.01f, 0.01f}, {0.05f, 0.08f}, {0.15f, 0.01f}, {-0.01f, 0.01f}};
  const auto kept = voxel_filter_2d(points, 0.1);
  ASSERT_EQ(kept.size(), 3u);  // the second point shares the first's cell
  EXPECT_EQ(kept[0], points[0]);
  EXPECT_EQ(kept[1], points[2]);
  EXPECT_EQ(kept[2], points[3]);
  EXPECT_EQ(voxel_filter_2d(points, 0.0).size(), points.size());
}

TEST(LaserScan, ABeamOnATeammateIsOneAtLeastThatBright) {
  LaserScan scan;
  scan.ranges_m = {1.f, 2.f, 3.f};
  EXPECT_FALSE(on_teammate(scan, 0, 0.9f)) << "no intensities: no teammate";
  scan.intensities = {0.2f, 0.9f, 1.f};
  EXPECT_FALSE(on_teammate(scan, 0, 0.9f));
  EXPECT_TRUE(on_teammate(scan, 1, 0.9f));
  EXPECT_TRUE(on_teammate(scan, 2, 0.9f));
  EXPECT_FALSE(on_teammate(scan, 2, 0.f)) << "threshold 0: off";
  scan.intensities.pop_back();
  EXPECT_FALSE(on_teammate(scan, 1, 0.9f)) << "intensities that do not match the ranges are not trusted";
}

}  // namespace
}  // namespace cairn

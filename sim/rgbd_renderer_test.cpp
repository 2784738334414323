#include "sim/rgbd_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace cairn::sim {
namespace {

// 20 m x 20 m open floor (origin at -10, -10), optionally with a wall at x = [wall_x, wall_x+0.05).
FloorPlan open_floor(double wall_x = 1e9) {
  const int n = 400;
  std::vector<uint8_t> cells(size_t(n) * n, 0);
  const int wall_col = wall_x < 1e8 ? int(std::floor((wall_x + 10.0) / 0.05)) : -1;
  for (int r = 0; wall_col >= 0 && r < n; ++r) cells[size_t(r) * n + size_t(wall_col)] = 1;
  return FloorPlan(n, n, 0.05, Eigen::Vector2d(-10, -10), cells);
}

WorldObject make_object(int id, ObjectShape shape, const Eigen::Vector3d& center, double size) {
  WorldObject o;
  o.id = id;
  o.object_class = "victim";
  o.shape = shape;
  o.color_rgb = {{220, 30, 30}};
  o.size_m = Eigen::Vector3d::Constant(size);
  o.center_m = center;
  return o;
}

CameraOptions noiseless() {
  CameraOptions c;
  c.depth_noise_sd_m = 0.0;
  return c;
}

TEST(RgbdRenderer, ObjectAtTheRightPixelAndDepth) {
  const CameraOptions options = noiseless();
  const std::vector<WorldObject> objects = {
      make_object(4, ObjectShape::kBox, {3.0, 0.0, 0.5}, 0.4),      // straight ahead
      make_object(9, ObjectShape::kSphere, {4.0, 1.0, 0.5}, 0.4)};  // 1 m to the left
  const RgbdRenderer renderer(options, open_floor(), 2.0, objects);
  std::mt19937_64 rng(3);
  std::vector<int> ids;
  const RgbdFrame f = renderer.render(SE2(), 42, rng, &ids);
  ASSERT_TRUE(f.valid());
  EXPECT_EQ(f.stamp_ns, 42);
  const CameraIntrinsics& k = f.intrinsics;
  auto at = [&](double u, double v) { return size_t(std::lround(v)) * size_t(k.width) + size_t(std::lround(u)); };
  // Box front face at x = 2.8, seen at the principal point.
  const size_t c = at(k.cx, k.cy);
  EXPECT_EQ(ids[c], 4);
  EXPECT_NEAR(f.depth[c] * k.depth_scale_m, 2.8, 0.02);
  EXPECT_GT(f.rgb[3 * c], 2 * f.rgb[3 * c + 1]);  // red
  // Sphere centre projects left of centre (optical x = -base y): u = cx - fx * 1 / 4.
  const size_t s = at(k.cx - k.fx * 1.0 / 4.0, k.cy);
  EXPECT_EQ(ids[s], 9);
  const double expected_z = (std::sqrt(17.0) - 0.2) * 4.0 / std::sqrt(17.0);  // range * cos(bearing)
  EXPECT_NEAR(f.depth[s] * k.depth_scale_m, expected_z, 0.03);
  // Floor below the horizon, nothing but ceiling above: the top row hits the ceiling (z = 2).
  const size_t top = at(k.cx, 0);
  EXPECT_EQ(ids[top], -1);
  const double ceiling_z = (2.0 - options.height_m) / (k.cy / k.fy);
  EXPECT_NEAR(f.depth[top] * k.depth_scale_m, ceiling_z, 0.01);
  const size_t bottom = at(k.cx, k.height - 1);
  EXPECT_NEAR(f.depth[bottom] * k.depth_scale_m, options.height_m / (k.cy / k.fy), 0.01);
}

TEST(RgbdRenderer, WallsOccludeObjectsAndBackgroundIsUnsaturated) {
  const CameraOptions options = noiseless();
  const RgbdRenderer renderer(options, open_floor(2.0), 2.0,
                              {make_object(1, ObjectShape::kCylinder, {3.0, 0.0, 0.5}, 0.5)});
  std::mt19937_64 rng(3);
  std::vector<int> ids;
  const RgbdFrame f = renderer.render(SE2(), 0, rng, &ids);
  for (int id : ids) EXPECT_EQ(id, -1);
  const CameraIntrinsics& k = f.intrinsics;
  const size_t c = size_t(k.cy) * size_t(k.width) + size_t(k.cx);
  EXPECT_NEAR(f.depth[c] * 0.001, 2.0, 0.01);  // wall face at x = 2.0
  for (size_t i = 0; i < ids.size(); ++i) {
    const int r = f.rgb[3 * i], g = f.rgb[3 * i + 1], b = f.rgb[3 * i + 2];
    const int mx = std::max({r, g, b}), mn = std::min({r, g, b});
    ASSERT_TRUE(mx == 0 || double(mx - mn) / mx < 0.3) << "saturated background at pixel " << i;
  }
}

TEST(RgbdRenderer, MoversAreDrawnThisOnceInFrontOfTheWorldsObjects) {
  const CameraOptions options = noiseless();
  const RgbdRenderer renderer(options, open_floor(), 2.0, {make_object(1, ObjectShape::kBox, {4.0, 0.0, 0.5}, 0.5)});
  WorldObject teammate = make_object(1001, ObjectShape::kCylinder, {2.0, 0.0, 0.2}, 0.4);
  teammate.color_rgb = {{30, 83, 230}};
  std::mt19937_64 rng(3);
  std::vector<int> ids;
  const RgbdFrame f = renderer.render(SE2(), 0, rng, &ids, {teammate});
  const CameraIntrinsics& k = f.intrinsics;
  const size_t ahead_low = size_t(k.cy + 20) * size_t(k.width) + size_t(k.cx);  // below the axis: the teammate
  EXPECT_EQ(ids[ahead_low], 1001);
  EXPECT_NEAR(f.depth[ahead_low] * 0.001, 1.8, 0.02);                           // its near face
  EXPECT_GT(f.rgb[3 * ahead_low + 2], f.rgb[3 * ahead_low]);                    // blue
  const size_t ahead_high = size_t(k.cy - 5) * size_t(k.width) + size_t(k.cx);  // above it: the box behind
  EXPECT_EQ(ids[ahead_high], 1);
  renderer.render(SE2(), 0, rng, &ids);  // gone again without movers
  EXPECT_EQ(std::count(ids.begin(), ids.end(), 1001), 0);
}

TEST(RgbdRenderer, DepthBeyondMaxIsZeroAndNoiseIsSeeded) {
  CameraOptions options;
  options.max_depth_m = 2.5;
  const RgbdRenderer renderer(options, open_floor(3.0), 2.0, {});
  std::mt19937_64 a(1), b(1), c(2);
  const RgbdFrame fa = renderer.render(SE2(), 0, a), fb = renderer.render(SE2(), 0, b);
  const RgbdFrame fc = renderer.render(SE2(), 0, c);
  EXPECT_EQ(fa.depth, fb.depth);
  EXPECT_NE(fa.depth, fc.depth);
  const CameraIntrinsics& k = fa.intrinsics;
  EXPECT_EQ(fa.depth[size_t(k.cy) * size_t(k.width) + size_t(k.cx)], 0);      // wall at 3 m > 2.5
  EXPECT_GT(fa.rgb[3 * (size_t(k.cy) * size_t(k.width) + size_t(k.cx))], 0);  // colour still drawn
}

TEST(RgbdRenderer, PitchedCameraSeesTheFloorCloser) {
  CameraOptions options = noiseless();
  options.pitch_deg = 20.0;
  const RgbdRenderer renderer(options, open_floor(), 2.0, {});
  std::mt19937_64 rng(1);
  const RgbdFrame f = renderer.render(SE2(), 0, rng);
  const CameraIntrinsics& k = f.intrinsics;
  // The principal ray hits the floor at range h / sin(pitch); z-depth along the axis is that range.
  const size_t c = size_t(std::lround(k.cy)) * size_t(k.width) + size_t(std::lround(k.cx));
  EXPECT_NEAR(f.depth[c] * 0.001, options.height_m / std::sin(20.0 * M_PI / 180.0), 0.03);
  const Eigen::Vector3d axis_base = renderer.T_base_camera().linear() * Eigen::Vector3d::UnitZ();
  EXPECT_LT(axis_base.z(), 0.0);  // looking down
}

TEST(RgbdRenderer, RenderTime) {
  const CameraOptions options;
  std::vector<WorldObject> objects;
  for (int i = 0; i < 10; ++i) {
    objects.push_back(make_object(i, ObjectShape(i % 3), {2.0 + 0.5 * i, -2.0 + 0.45 * i, 0.4}, 0.5));
  }
  const RgbdRenderer renderer(options, open_floor(8.0), 2.0, objects);
  std::mt19937_64 rng(1);
  const int n = 20;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) renderer.render(SE2(0, 0, 0.01 * i), i, rng);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  RecordProperty("render_ms", std::to_string(ms));
  std::printf("[ render ] %.2f ms per 320x240 frame with 10 objects\n", ms);
  EXPECT_LT(ms, 200.0);  // loose: debug builds and busy CI machines
}

}  // namespace
}  // namespace cairn::sim

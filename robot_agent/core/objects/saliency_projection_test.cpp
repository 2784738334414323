#include "robot_agent/core/objects/saliency_projection.h"

#include <gtest/gtest.h>

#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

/// Grey walls 4 m ahead; a red patch 2 m ahead of the camera, 0.5 m high, right of the centre.
RgbdFrame grey_room_with_red_patch(bool with_patch) {
  RgbdFrame f = testing::grey_wall_frame();
  if (with_patch) testing::paint_square(&f, 200, 100, 40, 220, 20, 20, 2000);
  return f;
}

TEST(SaliencyProjection, AColourfulPatchIsPlacedOnTheFloorAndGreyWallsAreNot) {
  const RgbdFrame f = grey_room_with_red_patch(true);
  const std::vector<SalientPoint> points = project_saliency(f, saliency_maps(f, {}));
  ASSERT_FALSE(points.empty());
  // The patch spans pixels u 200..240 at 2 m: (u - cx) z / fx = 0.31..0.62 m right of the camera
  // (base y -0.62..-0.31), 2 m ahead of it (base x 2.1). No grey wall point (4 m ahead) may appear.
  for (const SalientPoint& p : points) {
    EXPECT_NEAR(p.x_m, 2.1, 0.2) << p.x_m << ", " << p.y_m;
    EXPECT_GT(p.y_m, -0.7);
    EXPECT_LT(p.y_m, -0.25);
    EXPECT_GT(p.weight, 0.25f);
    EXPECT_LE(p.weight, 1.0f);
  }
  const RgbdFrame grey = grey_room_with_red_patch(false);
  EXPECT_TRUE(project_saliency(grey, saliency_maps(grey, {})).empty()) << "a grey frame draws nobody";
}

TEST(SaliencyProjection, PixelsWithoutDepthOrTooFarAreSkipped) {
  RgbdFrame f = grey_room_with_red_patch(true);
  std::fill(f.depth.begin(), f.depth.end(), 0);
  EXPECT_TRUE(project_saliency(f, saliency_maps(grey_room_with_red_patch(true), {})).empty());
  const RgbdFrame g = grey_room_with_red_patch(true);
  SaliencyProjectionOptions near;
  near.max_range_m = 1.5;
  EXPECT_TRUE(project_saliency(g, saliency_maps(g, {}), near).empty());
  EXPECT_TRUE(project_saliency(g, SaliencyMaps{}).empty());
}

TEST(SaliencyPool, PoolsPerCellInTheLocalFrameAndHandsOverFromTheKeyframe) {
  SaliencyProjectionOptions o;
  o.max_points_per_keyframe = 2;
  SaliencyPool pool(o);
  // The same spot (local (3, 1)) seen from two poses, and two weaker spots elsewhere.
  pool.add(SE2(1, 1, 0), {{2.0f, 0.0f, 0.5f}});
  pool.add(SE2(3, 0, M_PI / 2), {{1.0f, 0.0f, 0.8f}, {0.0f, -1.0f, 0.3f}});
  pool.add(SE2(0, 0, 0), {{-5.0f, -5.0f, 0.4f}});
  ASSERT_FALSE(pool.empty());
  const std::vector<SalientPoint> out = pool.take(SE2(3, 1, M_PI));
  EXPECT_TRUE(pool.empty());
  ASSERT_EQ(out.size(), 2u) << "the strongest max_points_per_keyframe";
  EXPECT_NEAR(out[0].x_m, 0.0, 1e-5);  // (3, 1) is the keyframe's own position
  EXPECT_NEAR(out[0].y_m, 0.0, 1e-5);
  EXPECT_FLOAT_EQ(out[0].weight, 0.8f) << "the stronger sighting of the cell";
  // Local (-5, -5) from a keyframe at (3, 1) facing -x: 8 m ahead and 6 m to its left.
  EXPECT_NEAR(out[1].x_m, 8.0, 1e-4);
  EXPECT_NEAR(out[1].y_m, 6.0, 1e-4);
}

}  // namespace
}  // namespace cairn::agent

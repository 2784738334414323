#include "base_station/core/global_map_renderer.h"

#include <gtest/gtest.h>

#include "base_station/core/synthetic_world_test_util.h"
#include "common/laser_scan.h"

namespace cairn::base {
namespace {

/// Poses are drawn shifted by this: walls and path points of the synthetic room sit on cell
/// borders, where grids of different origins may round a point into either neighbour.
const SE2 kOffGrid(0.01234, 0.00567, 0.0);

/// Robot 0 on the left path, robot 1 on the right path of the synthetic room (id order).
std::vector<Keyframe> room_keyframes() {
  std::vector<Keyframe> out = testing::make_keyframes(RobotId(0), testing::left_path(), testing::room_walls());
  for (Keyframe& k : testing::make_keyframes(RobotId(1), testing::right_path(), testing::room_walls()))
    out.push_back(k);
  for (Keyframe& k : out) k.scan.ranges_m[7] = k.scan.range_max_m;  // a no-return beam too
  return out;
}

/// The former global_map(): one grid, every keyframe once, in the given order.
OccupancyGrid plain_render(const std::vector<Keyframe>& kfs, const std::vector<SE2>& poses) {
  OccupancyGrid grid;
  for (size_t i = 0; i < kfs.size(); ++i) {
    std::vector<Eigen::Vector2f> no_return;
    for (size_t b = 0; b < kfs[i].scan.ranges_m.size(); ++b) {
      if (kfs[i].scan.ranges_m[b] < kfs[i].scan.range_max_m) continue;
      const float a = beam_angle_rad(kfs[i].scan, b), r = std::min(kfs[i].scan.range_max_m, 10.f);
      no_return.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    grid.insert_scan(poses[i], scan_to_points(kfs[i].scan), no_return);
  }
  return grid;
}

/// Cells of `a` that differ from `b` at the same world position (both ways), and the known ones.
int differing_cells(const OccupancyGrid& a, const OccupancyGrid& b, int* known) {
  int differ = 0;
  *known = 0;
  for (const auto& [x, y] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    for (int r = 0; r < x->height(); ++r) {
      for (int c = 0; c < x->width(); ++c) {
        const Eigen::Vector2i o = y->cell_of(x->cell_center_m(c, r));
        differ += x->log_odds(c, r) != y->log_odds(o.x(), o.y());
        *known += x == &a && x->known(c, r);
      }
    }
  }
  return differ;
}

GlobalMapRenderOptions exact_options(double tile_m) {
  GlobalMapRenderOptions o;
  o.tile_m = tile_m;
  o.min_move_m = 0.0;
  o.min_turn_rad = 0.0;
  return o;
}

TEST(GlobalMapRenderer, IncrementalRenderEqualsAFullRender) {
  const std::vector<Keyframe> kfs = room_keyframes();
  std::vector<SE2> poses;
  for (const Keyframe& k : kfs) {
    poses.push_back(kOffGrid * (k.id.robot == RobotId(0) ? testing::left_path()[size_t(k.id.seq)]
                                                         : testing::right_path()[size_t(k.id.seq)]));
  }
  GlobalMapRenderer renderer(OccupancyGridOptions{}, exact_options(3.0));  // small tiles: many borders
  for (size_t i = 0; i < kfs.size(); ++i) {
    renderer.set_pose(kfs[i], poses[i]);
    if (i % 4 == 3) renderer.render();  // new keyframes drawn on top as they come
  }
  renderer.render();
  // Robot 1 corrected by a loop closure; robot 0's last keyframe nudged.
  for (size_t i = 0; i < kfs.size(); ++i) {
    if (kfs[i].id.robot == RobotId(1)) poses[i] = SE2(0.2, -0.1, 0.03) * poses[i];
  }
  poses[5] = poses[5] * SE2(0.05, 0.0, 0.0);
  for (size_t i = 0; i < kfs.size(); ++i) renderer.set_pose(kfs[i], poses[i]);
  const OccupancyGrid& incremental = renderer.render();
  EXPECT_GT(renderer.last_stats().tiles, 0);
  int known = 0;
  EXPECT_EQ(differing_cells(incremental, plain_render(kfs, poses), &known), 0);
  EXPECT_GT(known, 1000);
  // Removing a keyframe: as if it had never been drawn.
  renderer.remove(kfs[2].id);
  std::vector<Keyframe> rest = kfs;
  std::vector<SE2> rest_poses = poses;
  rest.erase(rest.begin() + 2);
  rest_poses.erase(rest_poses.begin() + 2);
  EXPECT_EQ(differing_cells(renderer.render(), plain_render(rest, rest_poses), &known), 0);
}

TEST(GlobalMapRenderer, SmallMovesAreNotRedrawn) {
  const std::vector<Keyframe> kfs = room_keyframes();
  GlobalMapRenderOptions o;  // defaults: 3 cm, 0.003 rad
  GlobalMapRenderer renderer(OccupancyGridOptions{}, o);
  renderer.set_pose(kfs[0], testing::left_path()[0]);
  renderer.set_pose(kfs[1], testing::left_path()[1]);
  renderer.render();
  EXPECT_EQ(renderer.last_stats().keyframes_drawn, 2);
  EXPECT_EQ(renderer.last_stats().tiles, 0);  // new keyframes go on top, no tile re-render
  renderer.set_pose(kfs[0], testing::left_path()[0] * SE2(0.01, 0.01, 0.001));
  renderer.render();
  EXPECT_EQ(renderer.last_stats().tiles, 0);
  EXPECT_EQ(renderer.last_stats().keyframes_drawn, 0);
  renderer.set_pose(kfs[0], testing::left_path()[0] * SE2(0.0, 0.0, 0.01));
  renderer.render();
  EXPECT_GT(renderer.last_stats().tiles, 0);
  EXPECT_GE(renderer.last_stats().keyframes_drawn, 1);
}

TEST(OccupancyGridClip, ClippedInsertTouchesOnlyItsBoxAndMatchesInside) {
  const Keyframe k = room_keyframes()[3];
  const SE2 pose = kOffGrid * testing::left_path()[3];
  const std::vector<Eigen::Vector2f> hits = scan_to_points(k.scan);
  OccupancyGrid full, clipped;
  full.insert_scan(pose, hits);
  clipped.reserve({-1, -1}, {11, 7});
  clipped.update_cell(clipped.cell_of({0.5, 0.5}).x(), clipped.cell_of({0.5, 0.5}).y(), 1.0f);  // outside the box
  const Eigen::Vector2d lo(2.0, 2.0), hi(4.0, 5.0);
  clipped.insert_scan_clipped(pose, hits, {}, lo, hi);
  int inside = 0;
  for (int r = 0; r < clipped.height(); ++r) {
    for (int c = 0; c < clipped.width(); ++c) {
      const Eigen::Vector2d p = clipped.cell_center_m(c, r);
      const bool in = (p.array() >= lo.array()).all() && (p.array() < hi.array()).all();
      const Eigen::Vector2i f = full.cell_of(p);
      if (in) {
        inside += clipped.known(c, r);
        EXPECT_EQ(clipped.log_odds(c, r), full.log_odds(f.x(), f.y())) << p.transpose();
      } else if ((p - Eigen::Vector2d(0.5, 0.5)).norm() > 0.04) {
        EXPECT_FALSE(clipped.known(c, r)) << p.transpose();
      }
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_TRUE(clipped.known(clipped.cell_of({0.5, 0.5}).x(), clipped.cell_of({0.5, 0.5}).y()));
  clipped.clear_region(lo, hi);
  const Eigen::Vector2i c = clipped.cell_of({3.0, 3.5});
  EXPECT_FALSE(clipped.known(c.x(), c.y()));
}

}  // namespace
}  // namespace cairn::base

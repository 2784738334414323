// The NavMap: scans land at their pose in the local frame (walls occupied, beams free, behind the
// walls unknown), beams without a return clear only a few metres, and rubble that appears where
// the map said free is occupied within a few scans.
#include "robot_agent/core/navigation/nav_map.h"

#include <gtest/gtest.h>

#include "robot_agent/core/navigation/nav_test_util.h"

namespace cairn::agent {
namespace {

using testing::add_box;
using testing::ray_cast;
using testing::Segment;

double probability_at(const NavMap& map, const Eigen::Vector2d& p) {
  const Eigen::Vector2i c = map.grid().cell_of(p);
  return map.grid().probability(c.x(), c.y());
}
bool known_at(const NavMap& map, const Eigen::Vector2d& p) {
  const Eigen::Vector2i c = map.grid().cell_of(p);
  return map.grid().known(c.x(), c.y());
}

TEST(NavMap, ScansLandAtTheirPoseInTheLocalFrame) {
  std::vector<Segment> world;
  add_box(&world, 0, 0, 6, 4);
  NavMap map;
  EXPECT_DOUBLE_EQ(map.grid().resolution_m(), 0.1);
  // The local frame is the world here; the robot at (2, 1) facing north-east.
  const SE2 pose(2, 1, 0.7);
  map.insert(pose, ray_cast(world, pose, 0));
  EXPECT_EQ(map.scans_inserted(), 1);
  // One scan: walls occupied already (a hit outweighs a neighbouring beam's miss), free space
  // only where several beams crossed.
  EXPECT_GT(probability_at(map, {5.97, 2.0}), 0.65);  // the east wall
  EXPECT_GT(probability_at(map, {3.0, 3.97}), 0.65);  // the north wall
  EXPECT_LT(probability_at(map, {2.3, 1.3}), 0.25);   // beside the robot
  EXPECT_GT(probability_at(map, {4.0, 2.0}), 0.25);   // 2.2 m out: one or two misses, not yet free
  EXPECT_LT(probability_at(map, {4.0, 2.0}), 0.5);
  map.insert(pose, ray_cast(world, pose, 1));
  map.insert(pose, ray_cast(world, pose, 2));
  EXPECT_LT(probability_at(map, {4.0, 2.0}), 0.25);  // three scans: free
  EXPECT_LT(probability_at(map, {1.0, 3.0}), 0.25);
  EXPECT_FALSE(known_at(map, {6.5, 2.0}));  // behind the wall
  EXPECT_FALSE(known_at(map, {3.0, -0.5}));
}

TEST(NavMap, BeamsWithoutAReturnClearOnlyAFewMetres) {
  const std::vector<Segment> nothing;
  NavMapOptions o;
  o.no_return_clear_m = 4.0;
  NavMap map(o);
  map.insert(SE2(0, 0, 0), ray_cast(nothing, SE2(0, 0, 0), 0));
  EXPECT_LT(probability_at(map, {3.5, 0.05}), 0.5);
  EXPECT_LT(probability_at(map, {0.05, -3.5}), 0.5);
  EXPECT_FALSE(known_at(map, {4.5, 0.05}));
  EXPECT_FALSE(known_at(map, {0.05, 4.6}));
}

TEST(NavMap, RubbleThatAppearsIsOccupiedWithinAFewScans) {
  std::vector<Segment> world;
  add_box(&world, -5, -5, 5, 5);
  NavMap map;
  const SE2 pose(0, 0, 0);
  for (int i = 0; i < 50; ++i) map.insert(pose, ray_cast(world, pose, i));
  EXPECT_LT(probability_at(map, {1.02, 0.0}), 0.25);  // long seen free
  world.push_back({{1.0, -0.3}, {1.0, 0.3}});         // rubble 1 m ahead
  int scans = 0;
  while (probability_at(map, {1.02, 0.0}) <= 0.65 && scans < 20) map.insert(pose, ray_cast(world, pose, 50 + ++scans));
  EXPECT_LE(scans, 3);
  EXPECT_LT(probability_at(map, {0.5, 0.0}), 0.25);  // still free in front of it
}

TEST(NavMap, ATeammateInADoorwayIsNoWallTheDoorStaysOpen) {
  // A wall along x = 3 with a 1 m door (y in [-0.5, 0.5]); a teammate (bright beams) stands in it.
  std::vector<Segment> world{{{3, -5}, {3, -0.5}}, {{3, 0.5}, {3, 5}}};
  const SE2 pose(0, 0, 0);
  const auto with_teammate = [&](int seed) {
    std::vector<Segment> w = world;
    w.push_back({{2.8, -0.2}, {2.8, 0.2}});
    LaserScan scan = ray_cast(w, pose, seed);
    scan.intensities.assign(scan.ranges_m.size(), 0.2f);
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const double a = beam_angle_rad(scan, i), r = scan.ranges_m[i];
      if (std::abs(r * std::cos(a) - 2.8) < 0.02 && std::abs(r * std::sin(a)) <= 0.2) scan.intensities[i] = 1.0f;
    }
    return scan;
  };
  NavMap map;
  for (int i = 0; i < 10; ++i) map.insert(pose, with_teammate(i));
  EXPECT_LT(probability_at(map, {2.65, 0.0}), 0.25) << "free up to the teammate";
  EXPECT_LE(probability_at(map, {2.82, 0.0}), 0.5) << "the teammate is not a wall";
  EXPECT_GT(probability_at(map, {3.02, 2.0}), 0.65) << "the walls are";
  // Without the tag (or with it turned off) the same teammate would close the door.
  NavMapOptions untagged;
  untagged.teammate_min_intensity = 0.f;
  NavMap closed(untagged);
  for (int i = 0; i < 10; ++i) closed.insert(pose, with_teammate(i));
  EXPECT_GT(probability_at(closed, {2.82, 0.0}), 0.65);
}

}  // namespace
}  // namespace cairn::agent

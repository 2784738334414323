// Local map-consistency checks (select_near_keyframes, used by the merger for closures into already
// linked pairs): their cost must not grow with the map, yet an aliased closure must still be
// refuted by a contradiction near it, while a disagreement far from the closure (a door closed
// since another robot passed it, 40 m away) no longer decides.
#include <gtest/gtest.h>

#include "base_station/core/map_consistency.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::along;
using testing::Segment;

PlacedScans place(const std::vector<Keyframe>& keyframes, const std::vector<SE2>& poses, const SE2& T = SE2()) {
  PlacedScans out;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    out.keyframes.push_back(&keyframes[i]);
    out.T_frame_base.push_back(T * poses[i]);
  }
  return out;
}

/// A 60 m corridor (y in [0, 3]) with side rooms every 10 m: doors at x = 10k + 4 .. 10k + 5.
std::vector<Segment> corridor() {
  std::vector<Segment> w = {{{0, 0}, {60, 0}}, {{0, 0}, {0, 3}}, {{60, 0}, {60, 3}}};
  for (int k = 0; k < 6; ++k) {
    const double x = 10.0 * k;
    w.push_back({{x, 3}, {x + 4, 3}});
    w.push_back({{x + 5, 3}, {x + 10, 3}});
    w.push_back({{x, 3}, {x, 7}});  // room divider
    w.push_back({{x, 7}, {x + 10, 7}});
  }
  return w;
}

TEST(MapConsistencyLocal, SelectionKeepsNearestOnePerCellWithinRadiusUpToCap) {
  std::vector<Keyframe> kfs(6);
  PlacedScans side;
  const std::vector<SE2> poses = {SE2(30, 0, 0), SE2(1, 0, 0),   SE2(1.1, 0.1, 0),
                                  SE2(2, 0, 0),  SE2(0.2, 0, 0), SE2(1.05, 0.05, 1)};
  for (size_t i = 0; i < kfs.size(); ++i) side.keyframes.push_back(&kfs[i]), side.T_frame_base.push_back(poses[i]);
  MapConsistencyOptions o;
  o.local_radius_m = 10.0;
  o.local_thin_cell_m = 0.5;
  const PlacedScans near = select_near_keyframes(side, Eigen::Vector2d::Zero(), o);
  // (30, 0) is out of range; (1.1, 0.1) and (1.05, 0.05) share (1, 0)'s cell; nearest first.
  ASSERT_EQ(near.keyframes.size(), 3u);
  EXPECT_EQ(near.keyframes[0], &kfs[4]);
  EXPECT_EQ(near.keyframes[1], &kfs[1]);
  EXPECT_EQ(near.keyframes[2], &kfs[3]);
  EXPECT_DOUBLE_EQ(near.T_frame_base[2].x(), 2.0);
  o.local_max_keyframes = 2;
  EXPECT_EQ(select_near_keyframes(side, Eigen::Vector2d::Zero(), o).keyframes.size(), 2u);
  o.local_radius_m = 0.0;  // no radius: the far one comes back
  o.local_max_keyframes = 100;
  EXPECT_EQ(select_near_keyframes(side, Eigen::Vector2d::Zero(), o).keyframes.size(), 4u);
}

TEST(MapConsistencyLocal, AWallFarFromTheClosureDoesNotDecide) {
  // Robot A drove the whole corridor; robot B saw it later with a door across it at x = 45 (closed
  // since A passed) and stopped at x = 42, 3 m before it. Both placed right.
  std::vector<Segment> walls_b = corridor();
  walls_b.push_back({{45, 0}, {45, 3}});
  const std::vector<SE2> pa = along({{1, 1.5}, {59, 1.5}}), pb = along({{1, 1.5}, {42, 1.5}});
  const auto ka = testing::make_keyframes(RobotId(0), pa, corridor());
  const auto kb = testing::make_keyframes(RobotId(1), pb, walls_b);
  const PlacedScans a = place(ka, pa), b = place(kb, pb);
  const MapConsistencyResult whole = check_map_consistency(a, b);
  ASSERT_TRUE(whole.conclusive);
  ASSERT_FALSE(whole.consistent) << "the far wall no longer contradicts: the test lost its point";
  // A's beams through the door reach the corridor's far end, which B never saw: not explained.
  EXPECT_EQ(whole.explained_pieces, 0) << whole.reason;
  // A closure near x = 5: only the keyframes within local_radius_m of it are compared.
  const MapConsistencyOptions o;
  const Eigen::Vector2d closure_m(5, 1.5);
  const MapConsistencyResult local =
      check_map_consistency(select_near_keyframes(a, closure_m, o), select_near_keyframes(b, closure_m, o), o);
  EXPECT_TRUE(local.conclusive) << local.reason;
  EXPECT_TRUE(local.consistent) << local.reason;
  // Near the door the local check sees it.
  const Eigen::Vector2d near_door_m(40, 1.5);
  const MapConsistencyResult at_door =
      check_map_consistency(select_near_keyframes(a, near_door_m, o), select_near_keyframes(b, near_door_m, o), o);
  EXPECT_FALSE(at_door.consistent) << at_door.reason;
}

TEST(MapConsistency, AWallSeenOnlyFromFarAwayDoesNotAccuse) {
  // B sees the corridor's end wall only from 8-12 m, and 0.6 m short of where it is (what a
  // 3-4 deg heading error of a distant keyframe does): in A's free space, but not evidence of a
  // wrong placement. Seen from 2 m, the same displaced wall is.
  std::vector<Segment> walls_b = corridor();
  walls_b[1] = {{0.6, 0}, {0.6, 3}};
  const std::vector<SE2> pa = along({{1, 1.5}, {30, 1.5}});
  const auto ka = testing::make_keyframes(RobotId(0), pa, corridor());
  const std::vector<SE2> far = along({{8, 1.5}, {12, 1.5}}), near = along({{2.6, 1.5}, {12, 1.5}});
  const auto kfar = testing::make_keyframes(RobotId(1), far, walls_b);
  const auto knear = testing::make_keyframes(RobotId(1), near, walls_b);
  MapConsistencyOptions every_wall;
  every_wall.wall_max_range_m = 0.0;
  const MapConsistencyResult unfiltered = check_map_consistency(place(ka, pa), place(kfar, far), every_wall);
  ASSERT_FALSE(unfiltered.consistent) << "the far wall no longer contradicts: the test lost its point";
  const MapConsistencyResult from_far = check_map_consistency(place(ka, pa), place(kfar, far));
  EXPECT_TRUE(from_far.conclusive) << from_far.reason;
  EXPECT_TRUE(from_far.consistent) << from_far.reason;
  const MapConsistencyResult from_near = check_map_consistency(place(ka, pa), place(knear, near));
  EXPECT_FALSE(from_near.consistent) << from_near.reason;
}

TEST(MapConsistency, AnObjectOnlyOneRobotSawIsExplainedByTheRoomBothSawBehindIt) {
  // A 12 x 8 m room, both robots driving the same loop 1.5 m from its walls, placed right; a 2 x 1 m
  // cabinet stood in it when B passed, not when A did. B's cabinet lies in A's free space, but A's
  // beams through it end on walls B mapped too: the same room, a changed object.
  const std::vector<Segment> room = {{{0, 0}, {12, 0}}, {{12, 0}, {12, 8}}, {{12, 8}, {0, 8}}, {{0, 8}, {0, 0}}};
  std::vector<Segment> room_b = room;
  for (const Segment& s :
       std::vector<Segment>{{{5, 3.5}, {7, 3.5}}, {{7, 3.5}, {7, 4.5}}, {{7, 4.5}, {5, 4.5}}, {{5, 4.5}, {5, 3.5}}}) {
    room_b.push_back(s);
  }
  const std::vector<SE2> path = along({{1.5, 1.5}, {10.5, 1.5}, {10.5, 6.5}, {1.5, 6.5}, {1.5, 1.5}});
  const auto ka = testing::make_keyframes(RobotId(0), path, room);
  const auto kb = testing::make_keyframes(RobotId(1), path, room_b);
  MapConsistencyOptions never_explained;
  never_explained.explained_min_fraction = 0.0;
  const MapConsistencyResult strict = check_map_consistency(place(ka, path), place(kb, path), never_explained);
  ASSERT_FALSE(strict.consistent) << "the cabinet no longer contradicts: the test lost its point";
  const MapConsistencyResult m = check_map_consistency(place(ka, path), place(kb, path));
  EXPECT_TRUE(m.conclusive) << m.reason;
  EXPECT_TRUE(m.consistent) << m.reason;
  EXPECT_GE(m.explained_pieces, 1);
  // The contrary case, a wall whose far side only one robot saw, stays refuted:
  // MapConsistencyLocal.AWallFarFromTheClosureDoesNotDecide.
}

TEST(MapConsistencyLocal, AnAliasedClosureIsStillRefutedByAContradictionNearIt) {
  // Identical side rooms every 10 m: B placed 10 m off (a closure into the wrong room) agrees
  // with A's map almost everywhere; the corridor's end wall at x = 0 contradicts near the closure.
  const std::vector<SE2> pa = along({{1, 1.5}, {59, 1.5}}), pb = along({{11, 1.5}, {30, 1.5}});
  const auto ka = testing::make_keyframes(RobotId(0), pa, corridor());
  const auto kb = testing::make_keyframes(RobotId(1), pb, corridor());
  const PlacedScans a = place(ka, pa), b_alias = place(kb, pb, SE2(-10, 0, 0)), b_truth = place(kb, pb);
  MapConsistencyOptions o;
  o.local_radius_m = 6.0;  // much smaller than the maps: only the closure's surroundings
  for (const Eigen::Vector2d closure_m : {Eigen::Vector2d(2, 1.5), Eigen::Vector2d(5, 1.5)}) {
    const PlacedScans near_a = select_near_keyframes(a, closure_m, o);
    const PlacedScans near_b = select_near_keyframes(b_alias, closure_m, o);
    ASSERT_LT(near_a.keyframes.size(), ka.size() / 3);
    ASSERT_LT(near_b.keyframes.size(), kb.size());
    const MapConsistencyResult alias = check_map_consistency(near_a, near_b, o);
    EXPECT_TRUE(alias.conclusive) << alias.reason;
    EXPECT_FALSE(alias.consistent) << alias.reason;
  }
  const Eigen::Vector2d truth_closure_m(15, 1.5);
  const MapConsistencyResult truth = check_map_consistency(select_near_keyframes(a, truth_closure_m, o),
                                                           select_near_keyframes(b_truth, truth_closure_m, o), o);
  EXPECT_TRUE(truth.conclusive && truth.consistent) << truth.reason;
}

}  // namespace
}  // namespace cairn::base

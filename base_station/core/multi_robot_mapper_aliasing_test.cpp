// Perceptual aliasing in the merger: two wings of a building that are exact translated copies.
// Robots exploring different wings see identical rooms, so Scan Context + verification yield
// inter-robot closures that PCM finds mutually consistent; only the map-level check (corridor
// ends, outer walls) tells the hypothesis is wrong. The operator's alignment of a robot's map in the
// console is judged the same way: refined when right, refused with its reason on the look-alike
// wing. Runs without DDS.
#include <gtest/gtest.h>

#include <optional>

#include "base_station/core/map_consistency.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::along;
using testing::Segment;
using testing::two_wing_building;
using testing::west_route;

/// Both robots through the two-wing building; `robot1_start` (robot 1's start in robot 0's frame)
/// is told to the base when given, so the pair is linked from the start.
MultiRobotMapper run(const std::vector<SE2>& p0, const std::vector<SE2>& p1, const MapperOptions& options,
                     OptimizeResult* last, std::optional<SE2> robot1_start = std::nullopt) {
  MultiRobotMapper mapper(options);
  if (robot1_start) {
    mapper.set_robot_start(RobotId(0), SE2());
    mapper.set_robot_start(RobotId(1), *robot1_start);
  }
  const auto walls = two_wing_building();
  const auto k0 = testing::make_keyframes(RobotId(0), p0, walls), k1 = testing::make_keyframes(RobotId(1), p1, walls);
  // Interleaved arrival, optimised every 10 keyframes as the base does.
  for (size_t i = 0; i < std::max(k0.size(), k1.size()); ++i) {
    if (i < k0.size()) mapper.add_keyframe(k0[i]);
    if (i < k1.size()) mapper.add_keyframe(k1[i]);
    if (i % 10 == 9) *last = mapper.optimize();
  }
  *last = mapper.optimize();
  return mapper;
}

/// Largest distance between `robot`'s merged keyframe positions and its true path (world frame
/// mapped into the global frame by T_global_world).
double worst_position_error_m(const MultiRobotMapper& mapper, RobotId robot, const std::vector<SE2>& path,
                              const SE2& T_global_world) {
  double worst = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    const SE2 est = *mapper.global_pose({robot, int32_t(i)});
    worst = std::max(worst, (est.translation() - (T_global_world * path[i]).translation()).norm());
  }
  return worst;
}

TEST(MultiRobotMapperAliasing, RobotsInIdenticalWingsStayUnlinked) {
  const std::vector<SE2> p0 = along(west_route(0)), p1 = along(west_route(12));
  MapperOptions unchecked;
  unchecked.check_map_consistency = false;
  OptimizeResult r;
  // Precondition: without the map check the aliasing merges robot 1 about 12 m off.
  const MultiRobotMapper wrong = run(p0, p1, unchecked, &r);
  ASSERT_TRUE(wrong.linked(RobotId(1))) << "the world no longer aliases: the test lost its point";
  const SE2 err = (p0[0].inverse() * p1[0]).between(*wrong.global_pose({RobotId(1), 0}));
  EXPECT_GT(err.translation().norm(), 10.0);

  MultiRobotMapper mapper = run(p0, p1, MapperOptions{}, &r);
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  EXPECT_EQ(r.unlinked_robots, 1);
  EXPECT_TRUE(mapper.global_trajectory(RobotId(1)).empty());
  EXPECT_GE(mapper.link_stats().rejected_map_contradiction, 1);
  EXPECT_EQ(mapper.link_stats().linked, 0);
  for (const auto& s : mapper.robots()) {
    if (s.id == RobotId(1)) EXPECT_FALSE(s.linked);
  }
}

TEST(MultiRobotMapperAliasing, OverlappingRobotsAreLinkedPrecisely) {
  const std::vector<SE2> p0 = along(west_route(0));
  std::vector<Eigen::Vector2d> back = west_route(0);
  std::reverse(back.begin(), back.end());  // robot 1 retraces wing W from its east end
  const std::vector<SE2> p1 = along(back);
  OptimizeResult r;
  MultiRobotMapper mapper = run(p0, p1, MapperOptions{}, &r);
  ASSERT_TRUE(mapper.linked(RobotId(1)));
  EXPECT_EQ(mapper.link_stats().linked, 1);
  EXPECT_LT(worst_position_error_m(mapper, RobotId(1), p1, p0[0].inverse()), 0.05);
}

TEST(MultiRobotMapperAliasing, ARobotSeeingOnePlaceOfAnotherFromAlongItsPathIsLinked) {
  // Robot 0 only looks around in the corridor at room A's door; robot 1 drives the corridor and
  // tours room B. The closures join one place of robot 0 (< 2 m) to metres of robot 1's path:
  // their lever arm is on robot 1's side, and the map check judges the rest.
  std::vector<SE2> p0;
  for (int i = 0; i < 12; ++i) p0.emplace_back(3.0 + 0.1 * (i % 3), 1.0 + 0.02 * i, i * 0.5);
  const std::vector<SE2> p1 = along({{0.8, 1}, {10.5, 1}, {9, 1}, {9, 5}, {10.5, 7}, {8, 6.5}, {9, 5}, {9, 1}});
  std::vector<Eigen::Vector2d> xy0;
  for (const SE2& p : p0) xy0.push_back(p.translation());
  double extent0 = 0;
  for (const auto& p : xy0)
    for (const auto& q : xy0) extent0 = std::max(extent0, (p - q).norm());
  ASSERT_LT(extent0, MapperOptions().min_link_spread_m) << "robot 0 must stay in one place";
  OptimizeResult r;
  MultiRobotMapper mapper = run(p0, p1, MapperOptions{}, &r);
  ASSERT_TRUE(mapper.linked(RobotId(1)));
  EXPECT_LT(worst_position_error_m(mapper, RobotId(1), p1, p0[0].inverse()), 0.05);
}

TEST(MultiRobotMapperAliasing, AClosureFarOffALinkedPairIsDroppedUnchecked) {
  // Both starts told to the base (linked from the start), robots in the two identical wings: every
  // inter-robot closure is an alias 12 m off the estimate, no drift correction.
  const std::vector<SE2> p0 = along(west_route(0)), p1 = along(west_route(12));
  const SE2 robot1_start = p0[0].inverse() * p1[0];
  OptimizeResult r;
  MapperOptions unbounded;
  unbounded.linked_closure_max_correction_m = 1e9;
  unbounded.linked_closure_max_correction_rad = 1e9;
  const MultiRobotMapper checked = run(p0, p1, unbounded, &r, robot1_start);
  ASSERT_GT(checked.link_stats().linked_pair_checked, 0)
      << "no aliased closure into the linked pair: the test lost its point";
  EXPECT_EQ(checked.link_stats().linked_pair_implausible, 0);

  const MultiRobotMapper mapper = run(p0, p1, MapperOptions{}, &r, robot1_start);
  EXPECT_GT(mapper.link_stats().linked_pair_implausible, 0);
  EXPECT_EQ(mapper.link_stats().linked_pair_checked, 0);  // none needed the map check
  for (const LoopClosure& c : mapper.loop_closures()) EXPECT_EQ(c.a.robot, c.b.robot) << "an aliased closure entered";
  EXPECT_LT(worst_position_error_m(mapper, RobotId(1), p1, p0[0].inverse()), 0.1);
}

/// Worst disagreement of the accepted intra-robot closures of robot 0 with the true path.
double worst_intra_closure_error_m(const MultiRobotMapper& mapper, const std::vector<SE2>& path) {
  double worst = 0;
  for (const LoopClosure& c : mapper.loop_closures()) {
    if (c.a.robot != c.b.robot) continue;
    const SE2 truth = path[size_t(c.a.seq)].between(path[size_t(c.b.seq)]);
    worst = std::max(worst, truth.between(c.T_a_b).translation().norm());
  }
  return worst;
}

TEST(MultiRobotMapperAliasing, OneRobotThroughIdenticalWingsKeepsOnlyTrueClosures) {
  // One robot explores wing W, then wing E: its scans in E verify against W's identical rooms
  // 12 m back. Those closures agree with each other, so only the robot's own poses (loop-closed
  // by its SLAM) can tell them wrong.
  std::vector<Eigen::Vector2d> route = west_route(0);
  for (const auto& p : west_route(12)) route.push_back(p);
  const std::vector<SE2> path = along(route);
  const auto keyframes = testing::make_keyframes(RobotId(0), path, two_wing_building());
  auto run_one = [&](const MapperOptions& options) {
    MultiRobotMapper mapper(options);
    for (size_t i = 0; i < keyframes.size(); ++i) {
      mapper.add_keyframe(keyframes[i]);
      if (i % 10 == 9) mapper.optimize();
    }
    mapper.optimize();
    return mapper;
  };
  MapperOptions ungated;
  ungated.intra_closure_gate_m = 1e9;
  ungated.intra_closure_gate_rad = 1e9;
  const MultiRobotMapper wrong = run_one(ungated);
  ASSERT_GT(worst_intra_closure_error_m(wrong, path), 10.0) << "the wings no longer alias: the test lost its point";

  const MultiRobotMapper mapper = run_one(MapperOptions{});
  EXPECT_GE(mapper.link_stats().intra_rejected, 1);
  EXPECT_LT(worst_intra_closure_error_m(mapper, path), 0.1);
  EXPECT_LT(worst_position_error_m(mapper, RobotId(0), path, path[0].inverse()), 0.05);
}

TEST(MapConsistency, ShiftedCopyContradictsAndTruthAgrees) {
  const auto walls = two_wing_building();
  const std::vector<SE2> p0 = along(west_route(0)), p1 = along(west_route(12));
  const auto k0 = testing::make_keyframes(RobotId(0), p0, walls), k1 = testing::make_keyframes(RobotId(1), p1, walls);
  PlacedScans a, b_truth, b_alias;
  for (size_t i = 0; i < k0.size(); ++i) a.keyframes.push_back(&k0[i]), a.T_frame_base.push_back(p0[i]);
  for (size_t i = 0; i < k1.size(); ++i) {
    b_truth.keyframes.push_back(&k1[i]), b_truth.T_frame_base.push_back(p1[i]);
    b_alias.keyframes.push_back(&k1[i]), b_alias.T_frame_base.push_back(SE2(-12, 0, 0) * p1[i]);
  }
  const MapConsistencyResult truth = check_map_consistency(a, b_truth);
  EXPECT_TRUE(truth.consistent) << truth.reason;
  const MapConsistencyResult alias = check_map_consistency(a, b_alias);
  EXPECT_TRUE(alias.conclusive);
  EXPECT_FALSE(alias.consistent) << alias.contradiction_ratio;

  // The drawing shows what the check counted: a contradicting pixel per contradicting cell (two
  // cells of the two grids may share a pixel), and the truth's few stray ones.
  auto contradicting_pixels = [](const MapConsistencyImage& img) {
    int n = 0;
    for (size_t i = 0; i + 2 < img.rgb.size(); i += 3) {
      const uint8_t r = img.rgb[i], g = img.rgb[i + 1], b = img.rgb[i + 2];
      n += (r == 0 && g == 230 && b == 0) || (r == 255 && g == 150 && b == 0);
    }
    return n;
  };
  const MapConsistencyImage drawn = draw_map_consistency(a, b_alias);
  ASSERT_GT(drawn.width, 200);  // the 24 m building at 0.1 m plus the shifted copy's overhang
  ASSERT_EQ(drawn.rgb.size(), size_t(drawn.width) * drawn.height * 3);
  EXPECT_GE(contradicting_pixels(drawn), alias.contradicting_cells * 9 / 10);
  EXPECT_LE(contradicting_pixels(drawn), alias.contradicting_cells);
  EXPECT_LE(contradicting_pixels(draw_map_consistency(a, b_truth)), truth.contradicting_cells);
}

// The operator's alignment (robot_linker_operator.cpp).

TEST(MultiRobotMapperAliasing, AnOperatorsAlignmentAMetreOffIsRefinedToTheRightPlacement) {
  const std::vector<SE2> p0 = along(west_route(0));
  std::vector<Eigen::Vector2d> back = west_route(0);
  std::reverse(back.begin(), back.end());  // robot 1 retraces wing W from its east end
  const std::vector<SE2> p1 = along(back);
  MapperOptions no_loops;  // only the operator can link them
  no_loops.detect_loops = false;
  OptimizeResult r;
  MultiRobotMapper mapper = run(p0, p1, no_loops, &r);
  ASSERT_FALSE(mapper.linked(RobotId(1)));
  const SE2 truth = p0[0].inverse() * p1[0];
  const SE2 dragged = SE2(0.8, -0.6, 8.0 * M_PI / 180.0) * truth;  // 1 m and 8 deg off
  ASSERT_TRUE(mapper.request_alignment(RobotId(1), dragged));
  EXPECT_EQ(mapper.alignments().at(RobotId(1)).state, AlignmentState::kPending);
  mapper.optimize();
  const AlignmentVerdict& v = mapper.alignments().at(RobotId(1));
  ASSERT_EQ(v.state, AlignmentState::kAccepted) << v.reason;
  EXPECT_GE(v.closures, 3);
  EXPECT_LT((v.placed.translation() - truth.translation()).norm(), 0.1) << v.reason;
  ASSERT_TRUE(mapper.linked(RobotId(1)));
  EXPECT_LT(worst_position_error_m(mapper, RobotId(1), p1, p0[0].inverse()), 0.05);
  std::printf("[operator alignment] %s\n", v.reason.c_str());
  ASSERT_TRUE(mapper.request_alignment(RobotId(1), dragged));  // again: it is on the map already
  mapper.optimize();
  EXPECT_EQ(mapper.alignments().at(RobotId(1)).state, AlignmentState::kRefused);
  EXPECT_NE(mapper.alignments().at(RobotId(1)).reason.find("already on the map"), std::string::npos);
}

TEST(MultiRobotMapperAliasing, AnOperatorsAlignmentOntoTheLookAlikeWingIsRefusedWithItsReason) {
  const std::vector<SE2> p0 = along(west_route(0)), p1 = along(west_route(12));  // robot 1 in wing E
  OptimizeResult r;
  MultiRobotMapper mapper = run(p0, p1, MapperOptions{}, &r);
  ASSERT_FALSE(mapper.linked(RobotId(1)));
  const SE2 truth = p0[0].inverse() * p1[0];
  mapper.request_alignment(RobotId(1), SE2(-12.0, 0.0, 0.0) * truth);  // onto wing W, where it looks right
  mapper.optimize();
  const AlignmentVerdict& wrong = mapper.alignments().at(RobotId(1));
  EXPECT_EQ(wrong.state, AlignmentState::kRefused);
  EXPECT_NE(wrong.reason.find("map check refutes"), std::string::npos) << wrong.reason;
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  std::printf("[operator alignment] look-alike wing: %s\n", wrong.reason.c_str());
  // The true placement: robot 0 never saw wing E, so nothing there can confirm it (what the wide
  // search finds there are stray matches that disagree with each other).
  mapper.request_alignment(RobotId(1), truth);
  mapper.optimize();
  const AlignmentVerdict& unseen = mapper.alignments().at(RobotId(1));
  EXPECT_EQ(unseen.state, AlignmentState::kRefused);
  EXPECT_TRUE(unseen.reason.find("does not overlap") != std::string::npos ||
              unseen.reason.find("disagree") != std::string::npos)
      << unseen.reason;
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  EXPECT_FALSE(mapper.request_alignment(RobotId(1), SE2(std::nan(""), 0.0, 0.0)));
  EXPECT_FALSE(mapper.request_alignment(RobotId(), truth));
}

}  // namespace
}  // namespace cairn::base

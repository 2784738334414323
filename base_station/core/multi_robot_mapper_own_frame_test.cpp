// An unlinked robot's map as the base judges a link by it: the front end's keyframe poses drift, the
// base's own-frame solution (the robot's keyframes and its own loop closures) does not
// (MultiRobotMapper::refined_local_pose). Runs without DDS.
#include <gtest/gtest.h>

#include "base_station/core/map_consistency.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::along;
using testing::drifting_keyframes;

/// Worst position error of robot 1's poses (by `pose`) against its true path, in its own frame.
template <typename PoseFn>
double worst_error_m(const std::vector<SE2>& path_world, PoseFn pose) {
  double worst = 0;
  for (size_t i = 0; i < path_world.size(); ++i) {
    const SE2 truth = path_world.front().between(path_world[i]);
    worst = std::max(worst, (pose(int32_t(i)).translation() - truth.translation()).norm());
  }
  return worst;
}

TEST(MultiRobotMapperOwnFrame, AnUnlinkedRobotsOwnLoopClosuresStraightenTheMapItIsJudgedBy) {
  // Robot 1 tours wing W twice (corridor, both rooms) with 0.3 deg/m of heading drift; robot 0,
  // the anchor, is in another building, so robot 1 stays unlinked.
  std::vector<Eigen::Vector2d> route = testing::west_route(0), back = testing::west_route(0);
  std::reverse(back.begin(), back.end());
  route.insert(route.end(), back.begin() + 1, back.end());
  const std::vector<SE2> path1 = along(route);
  const auto k1 = drifting_keyframes(RobotId(1), path1, testing::two_wing_building(), 0.3 * M_PI / 180.0);
  const auto k0 = testing::make_keyframes(RobotId(0), testing::left_path(), testing::room_walls());

  MultiRobotMapper mapper;
  for (const Keyframe& kf : k0) mapper.add_keyframe(kf);
  for (size_t i = 0; i < k1.size(); ++i) {
    mapper.add_keyframe(k1[i]);
    if (i % 10 == 9) mapper.optimize();
  }
  mapper.optimize();
  ASSERT_FALSE(mapper.linked(RobotId(1))) << "robot 1 was linked to another building";

  // Precondition: the front end's map is bent by more than the map check's wall tolerance.
  const double front_end_m = worst_error_m(path1, [&](int32_t i) { return k1[size_t(i)].T_local_base; });
  ASSERT_GT(front_end_m, 0.6) << "the drift no longer bends the map: the test lost its point";
  const double refined_m = worst_error_m(path1, [&](int32_t i) { return mapper.refined_local_pose({RobotId(1), i}); });
  EXPECT_LT(refined_m, 0.2) << "front end " << front_end_m << " m";

  // The first half of the tour against the second, each placed by the refined poses: one map. By
  // the front end's poses the two passes contradict each other.
  auto half = [&](bool first, bool refined) {
    PlacedScans s;
    const size_t mid = k1.size() / 2;
    for (size_t i = first ? 0 : mid; i < (first ? mid : k1.size()); ++i) {
      s.keyframes.push_back(&k1[i]);
      s.T_frame_base.push_back(refined ? mapper.refined_local_pose(k1[i].id) : k1[i].T_local_base);
    }
    return s;
  };
  EXPECT_FALSE(check_map_consistency(half(true, false), half(false, false)).consistent);
  const MapConsistencyResult m = check_map_consistency(half(true, true), half(false, true));
  EXPECT_TRUE(m.consistent && m.conclusive) << m.reason;
}

/// What a robot agent whose own loop closing got its keyframes right sends (KeyframePoses).
KeyframePoses true_poses(RobotId robot, const std::vector<SE2>& path_world) {
  KeyframePoses update{robot, 0, {}};
  for (size_t i = 0; i < path_world.size(); ++i)
    update.poses.push_back({int32_t(i), path_world.front().between(path_world[i])});
  return update;
}

TEST(MultiRobotMapperOwnFrame, TheAgentsLoopClosedPosesReplaceTheDriftingFrontEndChain) {
  // Robot 0 (the anchor, placed) and robot 1 (another building, unlinked) both tour with 0.5 deg/m
  // of heading drift in their front ends; their agents then send loop-closed poses.
  const std::vector<SE2> path0 = along(testing::west_route(0));
  const std::vector<SE2> path1 = along({{1.5, 1.0}, {8.5, 1.0}, {8.5, 4.5}, {1.5, 4.5}});
  const double drift = 0.5 * M_PI / 180.0;
  const auto k0 = drifting_keyframes(RobotId(0), path0, testing::two_wing_building(), drift);
  const auto k1 = drifting_keyframes(RobotId(1), path1, testing::room_walls(), drift);
  MultiRobotMapper mapper;
  for (const Keyframe& kf : k0) mapper.add_keyframe(kf);
  for (const Keyframe& kf : k1) mapper.add_keyframe(kf);
  mapper.optimize();
  ASSERT_TRUE(mapper.linked(RobotId(0)));
  ASSERT_FALSE(mapper.linked(RobotId(1)));
  auto global0 = [&](int32_t i) { return *mapper.global_pose({RobotId(0), i}); };
  auto refined1 = [&](int32_t i) { return mapper.refined_local_pose({RobotId(1), i}); };
  const double before0_m = worst_error_m(path0, global0), before1_m = worst_error_m(path1, refined1);
  ASSERT_GT(before0_m, 0.3) << "the drift no longer bends the map: the test lost its point";
  ASSERT_GT(before1_m, 0.1) << "the drift no longer bends the map: the test lost its point";

  EXPECT_TRUE(mapper.add_keyframe_poses(true_poses(RobotId(0), path0)).stored());
  EXPECT_TRUE(mapper.add_keyframe_poses(true_poses(RobotId(1), path1)).stored());
  mapper.optimize();
  EXPECT_LT(worst_error_m(path0, global0), 0.05) << "before " << before0_m << " m";
  EXPECT_LT(worst_error_m(path1, refined1), 0.05) << "before " << before1_m << " m";

  // Bad estimates are refused whole, naming what is wrong; the last good one stays in force.
  KeyframePoses nan = true_poses(RobotId(1), path1);
  nan.poses[3].T_local_base = SE2(NAN, 0, 0);
  const AddResult r_nan = mapper.add_keyframe_poses(nan);
  EXPECT_EQ(r_nan.status, AddStatus::kRejected);
  EXPECT_NE(r_nan.reason.find("non-finite pose of seq 3"), std::string::npos) << r_nan.reason;
  KeyframePoses unordered = true_poses(RobotId(1), path1);
  std::swap(unordered.poses[1], unordered.poses[2]);
  unordered.poses[1].T_local_base = SE2(5, 5, 0);  // would bend the map if taken
  const AddResult r_order = mapper.add_keyframe_poses(unordered);
  EXPECT_EQ(r_order.status, AddStatus::kRejected);
  EXPECT_NE(r_order.reason.find("not ascending"), std::string::npos) << r_order.reason;
  mapper.optimize();
  EXPECT_LT(worst_error_m(path1, refined1), 0.05);
}

}  // namespace
}  // namespace cairn::base

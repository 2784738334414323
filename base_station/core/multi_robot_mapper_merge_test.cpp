// Tests of the merger: LAGO initialisation, PCM, loop verification and automatic linking of
// robots whose relative starts are unknown.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "base_station/core/lago_initializer.h"
#include "base_station/core/loop_verifier.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/pcm.h"
#include "base_station/core/synthetic_world_test_util.h"
#include "common/g2o_io.h"

namespace cairn::base {
namespace {

KeyframeId kf(int robot, int seq) { return KeyframeId{RobotId(robot), seq}; }

TEST(Lago, ReachesGlobalOptimumOfManhattanFromOdometry) {
  const std::string path = std::string(CAIRN_SHARED_DATA_DIR) + "/g2o_2d/manhattan.g2o";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "data absent: " << path;
  const G2oGraph g = read_g2o(path);
  KeyframePoseGraphOptions o;
  o.loop_loss.type = RobustLossType::kNone;
  KeyframePoseGraph graph(o);
  for (const auto& [k, p] : initialize_from_odometry(g)) graph.add_node(kf(k.robot, int(k.index)), p);
  for (const auto& e : g.edges) {
    graph.add_edge({kf(e.from.robot, int(e.from.index)), kf(e.to.robot, int(e.to.index)), e.T_from_to, e.information});
  }
  const auto init = lago_initialize(graph);
  ASSERT_TRUE(init.has_value());
  graph.set_estimates(*init);
  graph.solve();
  KeyframePoseGraphOptions so = o;
  so.residual = EdgeResidualType::kSeSync;
  KeyframePoseGraph polish(so);
  for (const auto& [id, p] : graph.estimates()) polish.add_node(id, p);
  for (const auto& e : graph.edges()) polish.add_edge(e);
  polish.solve();
  std::map<G2oKey, SE2> poses;
  for (const auto& [id, p] : polish.estimates()) poses[{id.robot.value, id.seq}] = p;
  EXPECT_NEAR(sesync_objective(g, poses), 6.432e3, 6.432e3 * 1e-3);
}

TEST(Pcm, MaximumCliqueRejectsTheWrongClosure) {
  // Two robots on straight lines; the truth: T_a_b = identity at matching seqs.
  std::map<KeyframeId, SE2> local;
  for (int i = 0; i < 10; ++i) {
    local[kf(0, i)] = SE2(i, 0, 0);
    local[kf(1, i)] = SE2(0, -i, -M_PI / 2);  // robot 1's frame is rotated by +90 deg
  }
  const LocalPoseFn pose = [&](KeyframeId id) { return local.at(id); };
  const Covariance3 cov = Covariance3::Identity() * 1e-3;
  std::vector<LoopClosure> c;
  for (int i : {1, 4, 7}) c.push_back({kf(0, i), kf(1, i), SE2(0.01, -0.01, 0.005), cov, 1});
  c.push_back({kf(0, 2), kf(1, 8), SE2(0.0, 0.0, 0.0), cov, 1});  // perceptual aliasing
  const std::vector<size_t> clique = pcm_max_clique(c, pose);
  EXPECT_EQ(clique, (std::vector<size_t>{0, 1, 2}));
}

TEST(LoopVerifier, FindsTheOffsetWithoutAGuess) {
  const auto walls = testing::room_walls();
  const SE2 map_pose(3.0, 3.0, 0.0), query_pose(4.2, 2.4, 0.25);
  const auto map_points = scan_to_points(testing::simulate_scan(map_pose, walls));
  const auto query = scan_to_points(testing::simulate_scan(query_pose, walls));
  LoopVerifierOptions o;
  o.angular_window_rad = M_PI;
  const LoopVerification v = verify_loop(map_points, query, SE2(), o);
  ASSERT_TRUE(v.accepted) << v.reason;
  const SE2 truth = map_pose.between(query_pose);
  EXPECT_NEAR((v.T_map_query.translation() - truth.translation()).norm(), 0.0, 0.05);
  EXPECT_NEAR(normalize_angle(v.T_map_query.yaw() - truth.yaw()), 0.0, 0.02);
  EXPECT_GT(v.covariance(0, 0), 0.0);
}

TEST(LoopVerifier, ACorridorMatchIsUncertainAlongTheCorridorOnly) {
  // A long corridor (walls y = 0 and y = 2) with one door jamb far away: the walls fix y and the
  // heading, little fixes x. The covariance must say so (a point-to-point Hessian would not).
  std::vector<testing::Segment> walls = {{{-30, 0}, {30, 0}}, {{-30, 2}, {30, 2}}};
  const SE2 map_pose(0.0, 1.0, 0.0), query_pose(0.3, 1.1, 0.05);
  const auto map_points = scan_to_points(testing::simulate_scan(map_pose, walls));
  const auto query = scan_to_points(testing::simulate_scan(query_pose, walls));
  LoopVerifierOptions o;
  o.linear_window_m = 1.0;
  o.angular_window_rad = 0.3;
  const LoopVerification v = verify_loop(map_points, query, SE2(0.3, 0.1, 0.05), o);
  ASSERT_TRUE(v.accepted) << v.reason;
  const double sigma_along_m = std::sqrt(v.covariance(0, 0)), sigma_across_m = std::sqrt(v.covariance(1, 1));
  EXPECT_LT(sigma_across_m, 0.05);
  EXPECT_GT(sigma_along_m, 10 * sigma_across_m) << "along " << sigma_along_m << " across " << sigma_across_m;
  // In a room every direction is fixed.
  const auto room = testing::room_walls();
  const LoopVerification r =
      verify_loop(scan_to_points(testing::simulate_scan(SE2(3, 3, 0), room)),
                  scan_to_points(testing::simulate_scan(SE2(3.2, 3.1, 0.1), room)), SE2(0.2, 0.1, 0.1), o);
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(std::sqrt(r.covariance(0, 0)), 0.05);
  EXPECT_LT(std::sqrt(r.covariance(1, 1)), 0.05);
}

using testing::long_path;
using testing::retrace;

TEST(MultiRobotMapperMerge, LinksRobotsWithoutStartHints) {
  MultiRobotMapper mapper;
  const auto walls = testing::room_walls();
  const auto p0 = long_path(), p1 = retrace(long_path());
  for (const Keyframe& k : testing::make_keyframes(RobotId(0), p0, walls)) mapper.add_keyframe(k);
  const auto kf1 = testing::make_keyframes(RobotId(1), p1, walls);
  EXPECT_EQ(mapper.add_keyframe(kf1[0]).status, AddStatus::kPending);
  for (size_t i = 1; i < kf1.size(); ++i) mapper.add_keyframe(kf1[i]);
  const OptimizeResult r = mapper.optimize();
  EXPECT_EQ(r.unlinked_robots, 0);
  EXPECT_GE(r.inter_robot_closures, 3);
  EXPECT_TRUE(r.full_resolve);
  ASSERT_TRUE(mapper.linked(RobotId(1)));
  // Robot 0 anchors: global = robot 0's local frame = world shifted by p0[0].
  const SE2 T_global_world = p0[0].inverse();
  for (size_t i = 0; i < p1.size(); ++i) {
    const SE2 truth = T_global_world * p1[i];
    const SE2 est = *mapper.global_pose(kf(1, int(i)));
    EXPECT_NEAR((est.translation() - truth.translation()).norm(), 0.0, 0.05) << i;
  }
  const auto robots = mapper.robots();
  EXPECT_TRUE(robots[0].anchor);
  EXPECT_GT(robots[1].inter_robot_closures, 0);
  // Converged, an update with nothing new reports the graph's cost, not 0 (summary.json's final_cost).
  OptimizeResult last = r;
  for (int i = 0; i < 20 && mapper.refinement_pending(); ++i) last = mapper.optimize();
  ASSERT_GT(last.solve.final_cost, 0.0);
  const OptimizeResult idle = mapper.optimize();
  EXPECT_EQ(idle.solve.reason, "nothing new");
  EXPECT_NEAR(idle.solve.final_cost, last.solve.final_cost, 1e-6 * last.solve.final_cost);
}

TEST(MultiRobotMapperMerge, RobotInAnotherBuildingStaysUnlinked) {
  MultiRobotMapper mapper;
  const auto walls = testing::room_walls();
  std::vector<testing::Segment> other = {{{0, 0}, {30, 0}}, {{0, 1.5}, {30, 1.5}}};  // a corridor
  std::vector<SE2> corridor_path;
  for (int i = 0; i < 10; ++i) corridor_path.push_back(SE2(2 + i, 0.75, 0));
  for (const Keyframe& k : testing::make_keyframes(RobotId(0), long_path(), walls)) mapper.add_keyframe(k);
  for (const Keyframe& k : testing::make_keyframes(RobotId(1), corridor_path, other)) {
    EXPECT_EQ(mapper.add_keyframe(k).status, AddStatus::kPending);
  }
  const OptimizeResult r = mapper.optimize();
  EXPECT_EQ(r.unlinked_robots, 1);
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  EXPECT_TRUE(mapper.global_trajectory(RobotId(1)).empty());
  EXPECT_EQ(r.inter_robot_closures, 0);
}

TEST(MultiRobotMapperMerge, NanKeyframeRejected) {
  MultiRobotMapper mapper;
  Keyframe k = testing::make_keyframes(RobotId(0), long_path(), testing::room_walls())[1];
  k.T_prev_this = SE2(std::nan(""), 0, 0);
  EXPECT_EQ(mapper.add_keyframe(k).status, AddStatus::kRejected);
}

}  // namespace
}  // namespace cairn::base

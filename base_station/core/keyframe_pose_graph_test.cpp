#include "base_station/core/keyframe_pose_graph.h"

#include <gtest/gtest.h>

#include <random>

namespace cairn::base {
namespace {

KeyframeId kf(int robot, int seq) { return KeyframeId{RobotId(robot), seq}; }

double position_rmse(const KeyframePoseGraph& graph, const std::map<KeyframeId, SE2>& truth) {
  double sum = 0;
  for (const auto& [id, T] : truth) sum += (graph.estimate(id)->translation() - T.translation()).squaredNorm();
  return std::sqrt(sum / truth.size());
}

TEST(KeyframePoseGraph, AnEdgeReMeasuredInTheLiveProblemSolvesLikeAFreshGraph) {
  // A chain of 4 with a loop edge; solved once (the live Ceres problem exists), then the middle
  // edge re-measured in place: the new solution equals a graph built with that measurement.
  auto build = [](const SE2& middle) {
    KeyframePoseGraph g;
    for (int i = 0; i < 4; ++i) g.add_node(kf(0, i), SE2(1.0 * i, 0, 0));
    g.add_edge({kf(0, 0), kf(0, 1), SE2(1, 0, 0), Eigen::Matrix3d::Identity() * 100, EdgeKind::kOdometry});
    g.add_edge({kf(0, 1), kf(0, 2), middle, Eigen::Matrix3d::Identity() * 100, EdgeKind::kOdometry});
    g.add_edge({kf(0, 2), kf(0, 3), SE2(1, 0, 0), Eigen::Matrix3d::Identity() * 100, EdgeKind::kOdometry});
    g.add_edge({kf(0, 0), kf(0, 3), SE2(3, 0.3, 0.1), Eigen::Matrix3d::Identity(), EdgeKind::kLoop});
    g.set_prior({kf(0, 0), SE2(), Eigen::Matrix3d::Identity() * 1e6});
    return g;
  };
  const SE2 remeasured(0.9, 0.2, 0.15);
  KeyframePoseGraph live = build(SE2(1, 0, 0));
  ASSERT_TRUE(live.solve().converged);
  const SE2 before = *live.estimate(kf(0, 3));
  ASSERT_TRUE(live.set_edge_measurement(1, remeasured, Eigen::Matrix3d::Identity() * 100));
  EXPECT_FALSE(live.set_edge_measurement(4, remeasured, Eigen::Matrix3d::Identity()));  // no such edge
  EXPECT_FALSE(live.set_edge_measurement(1, SE2(NAN, 0, 0), Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(live.set_edge_measurement(1, remeasured, Eigen::Matrix3d::Zero()));
  EXPECT_TRUE(live.edges()[1].T_from_to.vector().isApprox(remeasured.vector()));  // the failed calls changed nothing
  ASSERT_TRUE(live.solve().converged);
  KeyframePoseGraph fresh = build(remeasured);
  ASSERT_TRUE(fresh.solve().converged);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((live.estimate(kf(0, i))->vector() - fresh.estimate(kf(0, i))->vector()).norm(), 1e-6) << i;
  }
  EXPECT_GT((live.estimate(kf(0, 3))->translation() - before.translation()).norm(), 0.05)
      << "the re-measured edge moved nothing";
}

TEST(KeyframePoseGraph, SquareWithLoopIsExact) {
  // g2o-like square, 2 m sides, yaw crossing +-pi; initial estimates perturbed.
  const std::vector<SE2> truth = {{0, 0, 0}, {2, 0, M_PI / 2}, {2, 2, M_PI}, {0, 2, -M_PI / 2}};
  KeyframePoseGraph graph;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(graph.add_node(kf(0, i), truth[i] * SE2(0.3 * i, -0.2 * i, 0.2 * i)));
  }
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    ASSERT_TRUE(graph.add_edge({kf(0, i), kf(0, j), truth[i].between(truth[j]), Eigen::Matrix3d::Identity(),
                                i == 3 ? EdgeKind::kLoop : EdgeKind::kOdometry}));
  }
  ASSERT_TRUE(graph.set_prior({kf(0, 0), truth[0], Eigen::Matrix3d::Identity() * 1e6}));
  const PoseGraphSolveResult r = graph.solve();
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_GT(r.initial_cost, r.final_cost);
  EXPECT_LT(r.final_cost, 1e-12);
  for (int i = 0; i < 4; ++i) {
    const SE2 est = *graph.estimate(kf(0, i));
    EXPECT_NEAR(est.x(), truth[i].x(), 1e-6);
    EXPECT_NEAR(est.y(), truth[i].y(), 1e-6);
    EXPECT_NEAR(normalize_angle(est.yaw() - truth[i].yaw()), 0.0, 1e-6);
  }
}

TEST(KeyframePoseGraph, RejectsBadInput) {
  KeyframePoseGraph graph;
  EXPECT_TRUE(graph.add_node(kf(0, 0), SE2()));
  EXPECT_FALSE(graph.add_node(kf(0, 0), SE2()));
  EXPECT_FALSE(graph.add_node(kf(0, 1), SE2(NAN, 0, 0)));
  EXPECT_FALSE(graph.add_edge({kf(0, 0), kf(0, 7), SE2(), Eigen::Matrix3d::Identity(), EdgeKind::kOdometry}));
  graph.add_node(kf(0, 1), SE2(1, 0, 0));
  EXPECT_FALSE(graph.add_edge({kf(0, 0), kf(0, 1), SE2(), Eigen::Matrix3d::Zero(), EdgeKind::kOdometry}));
  EXPECT_TRUE(graph.add_edge({kf(0, 0), kf(0, 1), SE2(1, 0, 0), Eigen::Matrix3d::Identity(), EdgeKind::kOdometry}));
  EXPECT_EQ(graph.edges().size(), 1u);
  EXPECT_TRUE(KeyframePoseGraph().solve().converged);  // empty graph
}

/// Two robots driving noisy circles, intra-robot loop closures and inter-robot edges.
TEST(KeyframePoseGraph, NoisyTwoRobotGraphGetsCloserToTruth) {
  std::mt19937 rng(42);
  std::normal_distribution<double> noise_xy(0.0, 0.03), noise_yaw(0.0, 0.02);
  const int n = 30;
  std::map<KeyframeId, SE2> truth;
  for (int r = 0; r < 2; ++r) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      truth[kf(r, i)] = SE2(4 * r + 2 * std::cos(a), 2 * std::sin(a), a + M_PI / 2);
    }
  }
  KeyframePoseGraphOptions options;
  options.loop_loss = {RobustLossType::kHuber, 1.0};
  KeyframePoseGraph graph(options);
  const Eigen::Matrix3d info = Eigen::Vector3d(1 / 9e-4, 1 / 9e-4, 1 / 4e-4).asDiagonal();
  auto noisy = [&](const SE2& T) { return T * SE2(noise_xy(rng), noise_xy(rng), noise_yaw(rng)); };
  for (int r = 0; r < 2; ++r) {
    SE2 dead_reckoning = truth[kf(r, 0)];
    graph.add_node(kf(r, 0), dead_reckoning);
    graph.set_prior({kf(r, 0), truth[kf(r, 0)], Eigen::Matrix3d::Identity() * 1e6});
    for (int i = 1; i < n; ++i) {
      const SE2 z = noisy(truth[kf(r, i - 1)].between(truth[kf(r, i)]));
      dead_reckoning = dead_reckoning * z;
      graph.add_node(kf(r, i), dead_reckoning);
      graph.add_edge({kf(r, i - 1), kf(r, i), z, info, EdgeKind::kOdometry});
    }
  }
  const double before = position_rmse(graph, truth);
  // Incremental: solve the chains, then add closures and solve again (warm start).
  EXPECT_TRUE(graph.solve().converged);
  for (int r = 0; r < 2; ++r) {
    graph.add_edge({kf(r, n - 1), kf(r, 0), truth[kf(r, n - 1)].between(truth[kf(r, 0)]), info, EdgeKind::kLoop});
  }
  for (int i = 0; i < n; i += 5) {
    graph.add_edge({kf(0, i), kf(1, (i + 15) % n), noisy(truth[kf(0, i)].between(truth[kf(1, (i + 15) % n)])), info,
                    EdgeKind::kLoop});
  }
  const PoseGraphSolveResult r = graph.solve();
  EXPECT_TRUE(r.converged) << r.reason;
  const double after = position_rmse(graph, truth);
  EXPECT_LT(after, 0.5 * before) << "before " << before << " after " << after;
  EXPECT_LT(after, 0.1);
}

/// A noisy square walk of `n` nodes (one robot) with the loop edges that close it: truth, the
/// odometry edges and the loop edges (noise-free measurements of the truth, so the optimum is tight).
struct LoopWalk {
  std::vector<SE2> truth, odometry;
  std::vector<PoseGraphEdge> loops;
};

LoopWalk make_loop_walk(int n) {
  LoopWalk w;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise_xy(0.0, 0.02), noise_yaw(0.0, 0.01);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / (n / 2);  // two laps of a circle of radius 5 m
    w.truth.push_back(SE2(5.0 * std::cos(a), 5.0 * std::sin(a), a + M_PI / 2));
  }
  for (int i = 1; i < n; ++i) {
    w.odometry.push_back(w.truth[i - 1].between(w.truth[i]) * SE2(noise_xy(rng), noise_xy(rng), noise_yaw(rng)));
  }
  for (int i = n / 2; i < n; i += 5) {  // second lap sees the first
    w.loops.push_back({kf(0, i - n / 2), kf(0, i), w.truth[i - n / 2].between(w.truth[i]),
                       Eigen::Matrix3d::Identity() * 1e4, EdgeKind::kLoop});
  }
  return w;
}

TEST(KeyframePoseGraph, LocalSolveMovesOnlyTheActiveNodes) {
  const LoopWalk w = make_loop_walk(40);
  KeyframePoseGraph graph;
  ASSERT_TRUE(graph.add_node(kf(0, 0), w.truth[0]));
  ASSERT_TRUE(graph.set_prior({kf(0, 0), w.truth[0], Eigen::Matrix3d::Identity() * 1e6}));
  for (int i = 1; i < 20; ++i) {
    ASSERT_TRUE(graph.add_node(kf(0, i), *graph.estimate(kf(0, i - 1)) * w.odometry[i - 1]));
    ASSERT_TRUE(graph.add_edge(
        {kf(0, i - 1), kf(0, i), w.odometry[i - 1], Eigen::Matrix3d::Identity() * 1e3, EdgeKind::kOdometry}));
  }
  ASSERT_TRUE(graph.add_edge(
      {kf(0, 2), kf(0, 17), w.truth[2].between(w.truth[17]), Eigen::Matrix3d::Identity() * 100.0, EdgeKind::kLoop}));
  ASSERT_TRUE(graph.solve().converged);
  const std::map<KeyframeId, SE2> before = graph.estimates();
  // A new leaf far off its odometry: a local solve of {new, its predecessor} puts it at the
  // composition and leaves every node outside the window bit-for-bit where it was.
  ASSERT_TRUE(graph.add_node(kf(0, 20), SE2(50, 50, 1)));
  ASSERT_TRUE(
      graph.add_edge({kf(0, 19), kf(0, 20), w.odometry[19], Eigen::Matrix3d::Identity() * 1e3, EdgeKind::kOdometry}));
  PoseGraphSolveOptions local;
  local.active_nodes = {kf(0, 19), kf(0, 20)};
  const PoseGraphSolveResult r = graph.solve(local);
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_EQ(r.variable_blocks, 2);
  for (const auto& [id, T] : before) {
    const SE2 now = *graph.estimate(id);
    if (id == kf(0, 19)) {
      EXPECT_NEAR((now.translation() - T.translation()).norm(), 0.0, 1e-6);  // a leaf does not pull it
    } else {
      EXPECT_EQ(now.vector(), T.vector()) << to_string(id);
    }
  }
  const SE2 expected = *graph.estimate(kf(0, 19)) * w.odometry[19];
  EXPECT_NEAR((graph.estimate(kf(0, 20))->translation() - expected.translation()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(normalize_angle(graph.estimate(kf(0, 20))->yaw() - expected.yaw()), 0.0, 1e-6);
}

/// The mapper's scheme (local windows per new node, then warm-started full solves after loop
/// closures) must reach the optimum a batch solve of the same graph finds.
TEST(KeyframePoseGraph, WindowedUpdatesThenFullSolveReachTheBatchOptimum) {
  const int n = 60;
  const LoopWalk w = make_loop_walk(n);
  KeyframePoseGraph graph;
  ASSERT_TRUE(graph.add_node(kf(0, 0), w.truth[0]));
  ASSERT_TRUE(graph.set_prior({kf(0, 0), w.truth[0], Eigen::Matrix3d::Identity() * 1e6}));
  size_t next_loop = 0;
  bool refine = false;
  int full_solves = 0;
  for (int i = 1; i < n; ++i) {
    ASSERT_TRUE(graph.add_node(kf(0, i), *graph.estimate(kf(0, i - 1)) * w.odometry[i - 1]));
    ASSERT_TRUE(graph.add_edge(
        {kf(0, i - 1), kf(0, i), w.odometry[i - 1], Eigen::Matrix3d::Identity() * 1e3, EdgeKind::kOdometry}));
    PoseGraphSolveOptions local;
    local.max_iterations = 10;
    for (int j = std::max(0, i - 5); j <= i; ++j) local.active_nodes.push_back(kf(0, j));
    for (; next_loop < w.loops.size() && w.loops[next_loop].to.seq == i; ++next_loop) {
      ASSERT_TRUE(graph.add_edge(w.loops[next_loop]));
      for (int j = std::max(0, w.loops[next_loop].from.seq - 5); j <= i; ++j) local.active_nodes.push_back(kf(0, j));
      refine = true;
    }
    EXPECT_TRUE(graph.solve(local).variable_blocks <= i + 1);
    if (refine) {  // one bounded full solve per update until one converges
      PoseGraphSolveOptions full;
      full.max_iterations = 3;
      refine = !graph.solve(full).converged;
      ++full_solves;
    }
  }
  for (int k = 0; k < 20 && refine; ++k) refine = !graph.solve(PoseGraphSolveOptions{}).converged;
  EXPECT_FALSE(refine);
  EXPECT_GT(full_solves, 0);
  // Batch: the same graph from odometry, one full solve.
  KeyframePoseGraph batch;
  batch.add_node(kf(0, 0), w.truth[0]);
  batch.set_prior({kf(0, 0), w.truth[0], Eigen::Matrix3d::Identity() * 1e6});
  for (int i = 1; i < n; ++i) batch.add_node(kf(0, i), *batch.estimate(kf(0, i - 1)) * w.odometry[i - 1]);
  const std::map<KeyframeId, SE2> batch_init = batch.estimates();
  for (const PoseGraphEdge& e : graph.edges()) ASSERT_TRUE(batch.add_edge(e));
  ASSERT_TRUE(batch.solve().converged);
  double worst_m = 0, worst_rad = 0;
  for (int i = 0; i < n; ++i) {
    const SE2 a = *graph.estimate(kf(0, i)), b = *batch.estimate(kf(0, i));
    worst_m = std::max(worst_m, (a.translation() - b.translation()).norm());
    worst_rad = std::max(worst_rad, std::abs(normalize_angle(a.yaw() - b.yaw())));
  }
  EXPECT_LT(worst_m, 1e-4);
  EXPECT_LT(worst_rad, 1e-5);
  // And the loops did something: the laps agree where dead reckoning had them apart.
  double worst_loop_m = 0, worst_dead_reckoning_m = 0;
  for (const PoseGraphEdge& e : w.loops) {
    const SE2 est = graph.estimate(e.from)->between(*graph.estimate(e.to));
    const SE2 dr = batch_init.at(e.from).between(batch_init.at(e.to));
    worst_loop_m = std::max(worst_loop_m, (est.translation() - e.T_from_to.translation()).norm());
    worst_dead_reckoning_m = std::max(worst_dead_reckoning_m, (dr.translation() - e.T_from_to.translation()).norm());
  }
  EXPECT_LT(worst_loop_m, 0.05);
  EXPECT_GT(worst_dead_reckoning_m, 0.1);
}

}  // namespace
}  // namespace cairn::base

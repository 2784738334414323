#include "base_station/core/pose_graph_2d.h"

#include <gtest/gtest.h>

#include <random>

namespace cairn::base {
namespace {

KeyframeId kf(int robot, int seq) { return KeyframeId{RobotId(robot), seq}; }

double position_rmse(const PoseGraph2d& graph, const std::map<KeyframeId, SE2>& truth) {
  double sum = 0;
  for (const auto& [id, T] : truth) sum += (graph.estimate(id)->translation() - T.translation()).squaredNorm();
  return std::sqrt(sum / truth.size());
}

TEST(PoseGraph2d, SquareWithLoopIsExact) {
  // g2o-like square, 2 m sides, yaw crossing +-pi; initial estimates perturbed.
  const std::vector<SE2> truth = {{0, 0, 0}, {2, 0, M_PI / 2}, {2, 2, M_PI}, {0, 2, -M_PI / 2}};
  PoseGraph2d graph;
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

TEST(PoseGraph2d, RejectsBadInput) {
  PoseGraph2d graph;
  EXPECT_TRUE(graph.add_node(kf(0, 0), SE2()));
  EXPECT_FALSE(graph.add_node(kf(0, 0), SE2()));
  EXPECT_FALSE(graph.add_node(kf(0, 1), SE2(NAN, 0, 0)));
  EXPECT_FALSE(graph.add_edge({kf(0, 0), kf(0, 7), SE2(), Eigen::Matrix3d::Identity(), EdgeKind::kOdometry}));
  graph.add_node(kf(0, 1), SE2(1, 0, 0));
  EXPECT_FALSE(graph.add_edge({kf(0, 0), kf(0, 1), SE2(), Eigen::Matrix3d::Zero(), EdgeKind::kOdometry}));
  EXPECT_TRUE(graph.add_edge({kf(0, 0), kf(0, 1), SE2(1, 0, 0), Eigen::Matrix3d::Identity(), EdgeKind::kOdometry}));
  EXPECT_EQ(graph.edges().size(), 1u);
  EXPECT_TRUE(PoseGraph2d().solve().converged);  // empty graph
}

/// Two robots driving noisy circles, intra-robot loop closures and inter-robot edges.
TEST(PoseGraph2d, NoisyTwoRobotGraphGetsCloserToTruth) {
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
  PoseGraphOptions options;
  options.loop_loss = {RobustLossType::kHuber, 1.0};
  PoseGraph2d graph(options);
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
    graph.add_edge({kf(0, i), kf(1, (i + 15) % n), noisy(truth[kf(0, i)].between(truth[kf(1, (i + 15) % n)])),
                    info, EdgeKind::kLoop});
  }
  const PoseGraphSolveResult r = graph.solve();
  EXPECT_TRUE(r.converged) << r.reason;
  const double after = position_rmse(graph, truth);
  EXPECT_LT(after, 0.5 * before) << "before " << before << " after " << after;
  EXPECT_LT(after, 0.1);
}

}  // namespace
}  // namespace cairn::base

#include "robot_agent/core/submap_pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::agent {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(SubmapPoseGraph, AnisotropicSqrtInformationWeakensTheUncertainDirectionOnly) {
  // Isotropic covariance: the fixed weights.
  const Eigen::Matrix3d iso = anisotropic_sqrt_information(Eigen::Matrix3d::Identity() * 1e-4, 0.7, 50.0, 200.0, 0.05);
  EXPECT_TRUE(iso.isApprox(Eigen::Vector3d(50.0, 50.0, 200.0).asDiagonal().toDenseMatrix(), 1e-9)) << iso;
  // A corridor along x in the match frame, 100x the standard deviation along it; the constraint's
  // frame is rotated by 90 deg, so there the weak direction is y.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  cov.diagonal() << 1e-2, 1e-6, 1e-6;
  const Eigen::Matrix3d L = anisotropic_sqrt_information(cov, M_PI / 2, 50.0, 200.0, 0.05);
  EXPECT_NEAR(L(0, 0), 50.0, 1e-6);
  EXPECT_NEAR(L(1, 1), 50.0 * 0.05, 1e-6);  // 0.01 clamped to the floor ratio
  EXPECT_NEAR(L(0, 1), 0.0, 1e-6);
  EXPECT_NEAR(L(2, 2), 200.0, 1e-9);
}

// A loop closure that is weak along x (a corridor) corrects a drifted chain across the corridor but
// leaves the position along it to the chain.
TEST(SubmapPoseGraph, AnisotropicLoopClosureOnlyCorrectsTheConstrainedDirection) {
  auto solve = [](bool anisotropic) {
    SubmapPoseGraph graph;
    graph.add_submap(SE2());
    for (int n = 0; n < 10; ++n) {
      const SE2 local(0.5 * n, 0.0, 0.0);
      graph.add_node(local, local);
      graph.add_constraint({0, n, local, SubmapPoseGraphConstraint::Kind::kIntraSubmap, 1.0});
    }
    SubmapPoseGraphConstraint loop{0, 9, SE2(4.5 + 0.3, 0.3, 0.0), SubmapPoseGraphConstraint::Kind::kLoopClosure, 0.9};
    if (anisotropic) {
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      cov.diagonal() << 1.0, 1e-4, 1e-4;
      loop.has_sqrt_information = true;
      loop.sqrt_information = anisotropic_sqrt_information(cov, 0.0, 50.0, 200.0, 0.01);
    }
    graph.add_constraint(loop);
    EXPECT_TRUE(graph.optimize());
    return graph.node_pose(9);
  };
  const SE2 fixed = solve(false), shaped = solve(true);
  EXPECT_GT(fixed.x() - 4.5, 0.03);             // the fixed weight pulls along x too
  EXPECT_LT(std::abs(shaped.x() - 4.5), 0.01);  // the shaped one does not
  EXPECT_GT(shaped.y(), 0.03);                  // but still across
}

TEST(SubmapPoseGraph, LoopConstraintPullsADriftedChainBack) {
  SubmapPoseGraph graph;
  graph.add_submap(SE2());
  SE2 local;
  for (int i = 0; i < 40; ++i) {
    // A square of 10 steps per side in the local frame, with a yaw bias of 0.25 deg per step.
    const SE2 step = (i % 10 == 9) ? SE2(0.5, 0, M_PI / 2 + 0.25 * kDeg) : SE2(0.5, 0, 0.25 * kDeg);
    if (i > 0) local = local * step;
    const int n = graph.add_node(local, local);
    if (n == 0) graph.add_constraint({0, 0, SE2(), SubmapPoseGraphConstraint::Kind::kIntraSubmap, 1.0});
  }
  // The last node is truly back at the start, rotated by 4 x 90 deg - 0.5 m along x before it.
  graph.add_constraint({0, 39, SE2(-0.5, 0, 0), SubmapPoseGraphConstraint::Kind::kLoopClosure, 0.9});
  const double before = (graph.node_pose(39).translation() - Eigen::Vector2d(-0.5, 0)).norm();
  ASSERT_TRUE(graph.optimize());
  const double after = (graph.node_pose(39).translation() - Eigen::Vector2d(-0.5, 0)).norm();
  EXPECT_GT(before, 0.5);
  EXPECT_LT(after, 0.05);
}

}  // namespace
}  // namespace cairn::agent

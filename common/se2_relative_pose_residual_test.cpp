#include "common/se2_relative_pose_residual.h"

#include <ceres/numeric_diff_cost_function.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace cairn {
namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

struct Evaluation {
  Eigen::Vector3d r;
  RowMajor3 J_a, J_b;
};

Evaluation evaluate(const ceres::CostFunction& cost, const double* a, const double* b) {
  Evaluation out;
  const double* parameters[2] = {a, b};
  double* jacobians[2] = {out.J_a.data(), out.J_b.data()};
  EXPECT_TRUE(cost.Evaluate(parameters, out.r.data(), jacobians));
  return out;
}

TEST(Se2RelativePoseResidual, ValueAtAKnownCase) {
  // a at (1, 2) facing +y; b 3 m ahead of it, turned by 0.3 rad. Measured: 2.5 m ahead, 0.5 m to
  // the left, 0.2 rad. Error in a's frame: (0.5, -0.5, 0.1); weights 10/m, 100/rad.
  const double a[3] = {1.0, 2.0, M_PI / 2}, b[3] = {1.0, 5.0, M_PI / 2 + 0.3};
  const Eigen::Matrix3d L = Se2RelativePoseResidual::diagonal_sqrt_information(10.0, 100.0);
  for (YawWrap wrap : {YawWrap::kFmod, YawWrap::kFloor}) {
    const Se2RelativePoseResidual residual(SE2(2.5, 0.5, 0.2), L, wrap);
    Eigen::Vector3d r;
    ASSERT_TRUE(residual(a, b, r.data()));
    EXPECT_NEAR(r(0), 5.0, 1e-12);
    EXPECT_NEAR(r(1), -5.0, 1e-12);
    EXPECT_NEAR(r(2), 10.0, 1e-12);
  }
  // A full square-root information mixes the components: r = L e.
  Eigen::Matrix3d full;
  full << 2.0, 1.0, 0.5, 0.0, 3.0, -1.0, 0.0, 0.0, 4.0;
  const Se2RelativePoseResidual residual(SE2(2.5, 0.5, 0.2), full, YawWrap::kFloor);
  Eigen::Vector3d r;
  ASSERT_TRUE(residual(a, b, r.data()));
  EXPECT_NEAR((r - full * Eigen::Vector3d(0.5, -0.5, 0.1)).norm(), 0.0, 1e-12);
}

TEST(Se2RelativePoseResidual, YawErrorIsWrappedAndTheWrapsDifferOnlyAtPi) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double a[3] = {0.0, 0.0, 3.0}, b[3] = {0.0, 0.0, -3.0};  // turned by 2 pi - 6 rad
  for (YawWrap wrap : {YawWrap::kFmod, YawWrap::kFloor}) {
    Eigen::Vector3d r;
    ASSERT_TRUE(Se2RelativePoseResidual(SE2(), I, wrap)(a, b, r.data()));
    EXPECT_NEAR(r(2), 2.0 * M_PI - 6.0, 1e-12);
  }
  // Exactly half a turn: fmod gives +pi (as normalize_angle), floor -pi.
  const double c[3] = {0.0, 0.0, 0.0}, d[3] = {0.0, 0.0, M_PI};
  Eigen::Vector3d r_fmod, r_floor;
  ASSERT_TRUE(Se2RelativePoseResidual(SE2(), I, YawWrap::kFmod)(c, d, r_fmod.data()));
  ASSERT_TRUE(Se2RelativePoseResidual(SE2(), I, YawWrap::kFloor)(c, d, r_floor.data()));
  EXPECT_EQ(r_fmod(2), M_PI);
  EXPECT_EQ(r_floor(2), -M_PI);
}

TEST(Se2RelativePoseResidual, AutomaticJacobiansMatchNumericDifferentiation) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> xy(-10.0, 10.0), yaw(-M_PI, M_PI), weight(0.5, 10.0);
  for (YawWrap wrap : {YawWrap::kFmod, YawWrap::kFloor}) {
    int checked = 0;
    for (int trial = 0; checked < 20; ++trial) {
      ASSERT_LT(trial, 1000);
      const double a[3] = {xy(rng), xy(rng), yaw(rng)}, b[3] = {xy(rng), xy(rng), yaw(rng)};
      const SE2 z(xy(rng) * 0.2, xy(rng) * 0.2, yaw(rng));
      // Numeric differences across the +-pi cut of the yaw error are meaningless: keep away from it.
      if (std::abs(normalize_angle(b[2] - a[2] - z.yaw())) > M_PI - 0.1) continue;
      Eigen::Matrix3d L = Eigen::Matrix3d::Zero();  // upper triangular, positive diagonal (as an LLT factor)
      for (int i = 0; i < 3; ++i) {
        L(i, i) = weight(rng);
        for (int j = i + 1; j < 3; ++j) L(i, j) = weight(rng) - 5.0;
      }
      if (checked % 2 == 0) L = Se2RelativePoseResidual::diagonal_sqrt_information(weight(rng), weight(rng));
      const std::unique_ptr<ceres::CostFunction> automatic(Se2RelativePoseResidual::create(z, L, wrap));
      const ceres::NumericDiffCostFunction<Se2RelativePoseResidual, ceres::CENTRAL, 3, 3, 3> numeric(
          new Se2RelativePoseResidual(z, L, wrap));
      const Evaluation ea = evaluate(*automatic, a, b), en = evaluate(numeric, a, b);
      // Same value up to rounding (Eigen sums a row of L e in another order on doubles than on Jets).
      EXPECT_LT((ea.r - en.r).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + ea.r.norm()));
      EXPECT_LT((ea.J_a - en.J_a).cwiseAbs().maxCoeff(), 1e-6) << "J_a\n" << ea.J_a << "\nvs\n" << en.J_a;
      EXPECT_LT((ea.J_b - en.J_b).cwiseAbs().maxCoeff(), 1e-6) << "J_b\n" << ea.J_b << "\nvs\n" << en.J_b;
      ++checked;
    }
  }
}

}  // namespace
}  // namespace cairn

// Box footprint from a partial view (shape_fit.h): the L-shape closeness yaw and the completion of
// the sides a box hides from the camera; curved surfaces are not completed.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "robot_agent/core/objects/shape_fit.h"

namespace cairn::agent {
namespace {

// Points on the faces of a yawed box (footprint lx x ly, height h, on the floor at centre c) whose
// outward normals face `eye`, 2 cm spacing; the top face only when `top` (camera above it).
std::vector<Eigen::Vector3d> visible_box(double lx, double ly, double h, const Eigen::Vector2d& c, double yaw,
                                         const Eigen::Vector3d& eye, bool top) {
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  std::vector<Eigen::Vector3d> pts;
  auto add = [&](const Eigen::Vector2d& local, double z) {
    pts.emplace_back((c + R * local).x(), (c + R * local).y(), z);
  };
  const Eigen::Vector2d eye_local = R.transpose() * (eye.head<2>() - c);
  for (int axis = 0; axis < 2; ++axis) {
    const double half_n = axis == 0 ? lx / 2 : ly / 2, half_t = axis == 0 ? ly / 2 : lx / 2;
    for (const double side : {-1.0, 1.0}) {
      if (side * eye_local[axis] <= half_n) continue;  // face turned away
      for (double t = -half_t; t <= half_t + 1e-9; t += 0.02)
        for (double z = 0.0; z <= h + 1e-9; z += 0.02) {
          Eigen::Vector2d q;
          q[axis] = side * half_n, q[1 - axis] = t;
          add(q, z);
        }
    }
  }
  if (top)
    for (double x = -lx / 2; x <= lx / 2 + 1e-9; x += 0.02)
      for (double y = -ly / 2; y <= ly / 2 + 1e-9; y += 0.02) add(Eigen::Vector2d(x, y), h);
  return pts;
}

ShapeFitOptions victim_prior() {
  ShapeFitOptions o;
  o.box_footprint_prior_m = Eigen::Vector2d(1.6, 0.5);
  return o;
}

TEST(ShapeFit, ThinLShapeGetsTheBoxYawNotTheHypotenuse) {
  // Long face and end face seen, far part of the long face cut: a thin L whose minimum-area
  // rectangle follows the hypotenuse and puts the centre ~0.2 m off.
  const Eigen::Vector2d c(5.0, 2.0);
  const double yaw = 0.4;
  const Eigen::Vector3d eye(c.x() - 4.0, c.y() - 1.2, 0.5);
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : visible_box(1.6, 0.5, 0.3, c, yaw, eye, false)) {
    const Eigen::Vector2d local = Eigen::Rotation2Dd(-yaw) * (p.head<2>() - c);
    if (local.x() < 0.55) pts.push_back(p);  // the far 0.25 m of the box is not seen
  }
  const ShapeFit f = fit_box(pts);
  ASSERT_TRUE(f.converged);
  const double yaw_err = std::remainder(f.yaw_rad - yaw, M_PI / 2);
  EXPECT_LT(std::abs(yaw_err), 2.0 * M_PI / 180.0);
  EXPECT_LT((f.center_m.head<2>() - c).norm(), 0.15);
}

TEST(ShapeFit, BroadsideFaceIsCompletedAwayFromTheCamera) {
  const Eigen::Vector2d c(3.0, -1.0);
  const double yaw = 0.0;  // long side along x, seen from -y
  const Eigen::Vector3d eye(3.1, -4.5, 0.5);
  const auto pts = visible_box(1.6, 0.5, 0.3, c, yaw, eye, false);
  const ShapeFit plain = best_shape_fit(pts, eye);
  EXPECT_NEAR(plain.center_m.y(), c.y() - 0.25, 0.03);  // the visible face: biased toward the camera
  const ShapeFit done = best_shape_fit(pts, eye, victim_prior());
  ASSERT_EQ(done.kind, ShapeKind::kBox);
  EXPECT_LT((done.center_m.head<2>() - c).norm(), 0.03);
  EXPECT_NEAR(std::min(done.size_m.x(), done.size_m.y()), 0.5, 1e-9);
}

TEST(ShapeFit, EndFaceSeenAloneIsCompletedToTheLongSide) {
  const Eigen::Vector2d c(0.0, 0.0);
  const Eigen::Vector3d eye(-4.0, 0.1, 0.5);  // looking along the long axis at the end face
  const ShapeFit f = best_shape_fit(visible_box(1.6, 0.5, 0.3, c, 0.0, eye, false), eye, victim_prior());
  EXPECT_LT((f.center_m.head<2>() - c).norm(), 0.05);
}

TEST(ShapeFit, CurvedSurfaceAndSmallFlatPatchAreNotCompleted) {
  // Visible half of a 0.5 m cylinder: curved, so never stretched to a 1.6 m box.
  std::vector<Eigen::Vector3d> half;
  for (int k = 0; k <= 40; ++k)
    for (double z = 0.0; z <= 1.0; z += 0.02) {
      const double a = M_PI / 2 + M_PI * k / 40.0;  // facing -x
      half.emplace_back(0.25 * std::cos(a), 0.25 * std::sin(a), z);
    }
  const Eigen::Vector3d eye(-4.0, 0.0, 0.5);
  const ShapeFit cyl = best_shape_fit(half, eye, victim_prior());
  EXPECT_LT(cyl.center_m.head<2>().norm(), 0.06) << to_string(cyl.kind);
  // A flat 0.3 m patch matches neither prior side: no interpretation, no completion.
  std::vector<Eigen::Vector3d> patch;
  for (double y = -0.15; y <= 0.15; y += 0.02)
    for (double z = 0.0; z <= 0.3; z += 0.02) patch.emplace_back(2.0, y, z);
  const ShapeFit p = best_shape_fit(patch, Eigen::Vector3d(0, 0, 0.5), victim_prior());
  EXPECT_NEAR(p.center_m.x(), 2.0, 0.02);
}

}  // namespace
}  // namespace cairn::agent

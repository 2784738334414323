#include "common/se2.h"

#include <gtest/gtest.h>

namespace cairn {
namespace {

TEST(SE2, ComposeThenInverseIsIdentity) {
  const SE2 a(1.0, 2.0, 0.7), b(-0.5, 0.3, -2.9);
  const SE2 c = a * b;
  const SE2 back = a.inverse() * c;
  EXPECT_NEAR(back.x(), b.x(), 1e-12);
  EXPECT_NEAR(back.y(), b.y(), 1e-12);
  EXPECT_NEAR(back.yaw(), b.yaw(), 1e-12);
  EXPECT_NEAR((a * a.inverse()).translation().norm(), 0.0, 1e-12);
}

TEST(SE2, TransformsPointsAndWrapsAngles) {
  const SE2 T(1.0, 0.0, M_PI / 2);
  const Eigen::Vector2d p = T * Eigen::Vector2d(1.0, 0.0);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 1.0, 1e-12);
  EXPECT_NEAR(SE2(0, 0, 3 * M_PI).yaw(), M_PI, 1e-12);
  EXPECT_NEAR(normalize_angle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(normalize_angle(2 * M_PI + 0.1), 0.1, 1e-12);
}

TEST(SE2, BetweenAndIsometryAgree) {
  const SE2 a(0.2, -1.0, 0.4), b(3.0, 1.0, -0.4);
  const SE2 d = a.between(b);
  const Eigen::Isometry3d D = a.to_isometry3().inverse() * b.to_isometry3();
  const SE2 d3 = SE2::from_isometry3(D);
  EXPECT_NEAR(d.x(), d3.x(), 1e-12);
  EXPECT_NEAR(d.y(), d3.y(), 1e-12);
  EXPECT_NEAR(d.yaw(), d3.yaw(), 1e-12);
}

TEST(SE2, InterpolateTakesTheShortArc) {
  const SE2 a(0, 0, M_PI - 0.1), b(2, 0, -M_PI + 0.1);
  const SE2 m = SE2::interpolate(a, b, 0.5);
  EXPECT_NEAR(m.x(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(m.yaw()), M_PI, 1e-9);
}

}  // namespace
}  // namespace cairn

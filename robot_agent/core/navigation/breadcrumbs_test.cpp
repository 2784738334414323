#include "robot_agent/core/navigation/breadcrumbs.h"

#include <gtest/gtest.h>

namespace cairn::agent {
namespace {

double length(const std::vector<Eigen::Vector2d>& way) {
  double l = 0;
  for (size_t i = 1; i < way.size(); ++i) l += (way[i] - way[i - 1]).norm();
  return l;
}

TEST(Breadcrumbs, TheWayBackFollowsTheDrivenPathAndCutsItsLoops) {
  Breadcrumbs crumbs;
  EXPECT_TRUE(crumbs.way({0, 0}, {1, 1}).empty());
  // East 10 m along y = 0, a 4 m x 4 m loop back through (5, 0), then north 5 m from there.
  for (double x = 0; x <= 10; x += 0.1) crumbs.add({x, 0});
  for (double y = 0; y <= 4; y += 0.1) crumbs.add({10, y});
  for (double x = 10; x >= 5; x -= 0.1) crumbs.add({x, 4});
  for (double y = 4; y >= 0; y -= 0.1) crumbs.add({5, y});  // back onto the first leg at (5, 0)
  for (double y = 0; y >= -5; y -= 0.1) crumbs.add({5, y});
  EXPECT_GT(crumbs.size(), 45u);  // 28 m of driving, a crumb every 0.5-0.6 m
  EXPECT_LT(crumbs.size(), 60u);
  const auto way = crumbs.way({5.1, -5.0}, {0, 0});
  ASSERT_GE(way.size(), 3u);
  EXPECT_EQ(way.front(), Eigen::Vector2d(5.1, -5.0));
  EXPECT_EQ(way.back(), Eigen::Vector2d(0, 0));
  // Straight back: 5 m south leg + 5 m west, not round the 18 m loop.
  EXPECT_NEAR(length(way), 10.1, 0.3);
  for (const auto& p : way) EXPECT_LT(p.y(), 0.6) << "the loop (y up to 4 m) is cut: " << p.transpose();
}

}  // namespace
}  // namespace cairn::agent

#include "common/keep_out.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn {
namespace {

TEST(KeepOut, AnAreaCarriedIntoARobotsFrameHoldsTheSamePoints) {
  const KeepOutArea area{7, {2.0, 1.0}, {4.0, 2.0}};
  const SE2 T_global_local(5.0, -3.0, 0.6);  // where the robot's frame sits on the merged map
  const KeepOutPolygon local = in_frame(area, T_global_local.inverse());
  EXPECT_EQ(local.id, 7u);
  EXPECT_FALSE(polygon_fault(local).has_value());
  for (double x = 1.5; x <= 4.5; x += 0.25) {
    for (double y = 0.5; y <= 2.5; y += 0.25) {
      const Eigen::Vector2d p_global(x, y);
      EXPECT_EQ(local.contains(T_global_local.inverse() * p_global), area.contains(p_global)) << x << ", " << y;
    }
  }
}

TEST(KeepOut, EitherWindingWorksAndTheBoundingBoxHoldsTheCorners) {
  KeepOutPolygon p{1, {Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 2), Eigen::Vector2d(2, 2), Eigen::Vector2d(2, 0)}};
  EXPECT_TRUE(p.contains({1, 1}));
  EXPECT_TRUE(p.contains({2, 1}));  // on an edge
  EXPECT_FALSE(p.contains({2.1, 1}));
  EXPECT_EQ(p.min_m(), Eigen::Vector2d(0, 0));
  EXPECT_EQ(p.max_m(), Eigen::Vector2d(2, 2));
}

TEST(KeepOut, ABadPolygonIsNamedWithWhatIsWrong) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  KeepOutPolygon p{3, {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(1, nan), Eigen::Vector2d(0, 1)}};
  EXPECT_EQ(polygon_fault(p).value_or(""), "keep-out area 3: a corner is not a finite number");
  p.corners_m = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)};
  EXPECT_EQ(polygon_fault(p).value_or(""), "keep-out area 3: its corners are not in convex order");
  p.corners_m = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(2, 0), Eigen::Vector2d(3, 0)};
  EXPECT_EQ(polygon_fault(p).value_or(""), "keep-out area 3: its corners enclose no area");
}

TEST(KeepOut, TheAreaARobotStandsInDoesNotTrapIt) {
  const std::vector<KeepOutPolygon> areas = {in_frame({1, {0, 0}, {2, 2}}, SE2()),
                                             in_frame({2, {5, 5}, {6, 6}}, SE2())};
  const auto closed = closed_around(areas, {1, 1});
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_EQ(closed[0].id, 2u);
  EXPECT_EQ(closed_around(areas, {3, 3}).size(), 2u);
  // With a margin: far off, each area is closed grown; within one's margin, that one without it.
  const auto far = closed_around(areas, {3.5, 3.5}, 0.3);
  ASSERT_EQ(far.size(), 2u);
  EXPECT_TRUE(far[1].contains({4.75, 5.5}));
  const auto near = closed_around(areas, {4.8, 5.5}, 0.3);
  ASSERT_EQ(near.size(), 2u);
  EXPECT_FALSE(near[1].contains({4.8, 5.5})) << "a robot within the margin must be free to leave it";
  EXPECT_TRUE(near[1].contains({5.0, 5.5}));
}

TEST(KeepOut, GrowingMovesEveryEdgeOutByTheMarginInEitherWindingAndAnyTurn) {
  const KeepOutArea box{4, {1, 2}, {3, 3}};
  for (const double yaw : {0.0, 0.4, -2.0}) {
    KeepOutPolygon p = in_frame(box, SE2(0.5, -1, yaw));
    for (const bool reversed : {false, true}) {
      if (reversed) std::reverse(p.corners_m.begin(), p.corners_m.end());
      const KeepOutPolygon g = grown(p, 0.25);
      EXPECT_FALSE(polygon_fault(g).has_value());
      const SE2 T_box_frame = SE2(0.5, -1, yaw).inverse();
      for (const auto& c : g.corners_m) {
        const Eigen::Vector2d b = T_box_frame * c;  // back in the box's frame: a corner of [0.75, 3.25] x [1.75, 3.25]
        EXPECT_NEAR(std::min(std::abs(b.x() - 0.75), std::abs(b.x() - 3.25)), 0.0, 1e-9) << yaw;
        EXPECT_NEAR(std::min(std::abs(b.y() - 1.75), std::abs(b.y() - 3.25)), 0.0, 1e-9) << yaw;
      }
    }
  }
}

}  // namespace
}  // namespace cairn

// The ROS 2 messages the base publishes (cairn_base --ros2), built from a small merged map: the
// grid's cells in ROS's occupancy scale and layout, the frames, the object markers and clouds.
#include "base_station/app/ros2_output.h"

#include <gtest/gtest.h>

#include <cstring>

namespace cairn::base {
namespace {

struct Fixture {
  OccupancyGrid grid{OccupancyGridOptions{}, Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 2)};
  MergedMap merged;
  Fixture() {
    grid.update_cell(0, 0, 4.0f);   // occupied, at the origin corner
    grid.update_cell(1, 0, -4.0f);  // free, next to it
    merged.grid = &grid;
    RobotSummary anchor, linked, pending;
    anchor.id = RobotId(0);
    anchor.linked = true;
    linked.id = RobotId(1);
    linked.linked = true;
    linked.T_global_local = SE2(3.0, -2.0, 0.5);
    pending.id = RobotId(2);  // not placed: no frame on the map
    merged.robots = {anchor, linked, pending};
    GlobalObject victim;
    victim.id = ObjectId{RobotId(1), 4};
    victim.class_name = "victim";
    victim.confidence = 0.93f;
    victim.position_m = Eigen::Vector3d(2.0, 1.0, 0.2);
    victim.size_m = Eigen::Vector3f(1.6f, 0.5f, 0.3f);
    victim.covariance = Eigen::Vector3d(0.04, 0.01, 0.0025).asDiagonal();
    victim.cloud_global = {{1.f, 2.f, 3.f, 255, 16, 1}, {4.f, 5.f, 6.f, 0, 0, 0}};
    merged.objects = {victim};
  }
};

TEST(Ros2Output, TheGridIsInRosOccupancyPercentWithRowZeroAtTheOrigin) {
  Fixture f;
  const auto m = to_occupancy_grid(f.grid, 5'000'000'123);
  EXPECT_EQ(m.header().frame_id(), "map");
  EXPECT_EQ(m.header().stamp().sec(), 5);
  EXPECT_EQ(m.header().stamp().nanosec(), 123u);
  EXPECT_EQ(m.info().width(), uint32_t(f.grid.width()));
  EXPECT_EQ(m.info().height(), uint32_t(f.grid.height()));
  EXPECT_FLOAT_EQ(m.info().resolution(), 0.05f);
  EXPECT_DOUBLE_EQ(m.info().origin().position().x(), f.grid.origin_m().x());
  ASSERT_EQ(m.data().size(), size_t(f.grid.width()) * size_t(f.grid.height()));
  EXPECT_EQ(int8_t(m.data()[0]), 98);  // log-odds 4 -> p 0.982
  EXPECT_EQ(int8_t(m.data()[1]), 2);
  EXPECT_EQ(int8_t(m.data()[2]), -1);  // never seen
}

TEST(Ros2Output, FramesHangOffTheMapForPlacedRobotsOnly) {
  Fixture f;
  const auto tf = to_tf(f.merged, {{RobotId(1), SE2(1.0, 0.0, 0.0)}, {RobotId(2), SE2()}}, 7);
  ASSERT_EQ(tf.transforms().size(), 3u);  // map->robot0/odom, map->robot1/odom, robot1/odom->robot1/base_link
  const auto& r1 = tf.transforms()[1];
  EXPECT_EQ(r1.header().frame_id(), "map");
  EXPECT_EQ(r1.child_frame_id(), "robot1/odom");
  EXPECT_DOUBLE_EQ(r1.transform().translation().x(), 3.0);
  EXPECT_NEAR(2.0 * std::atan2(r1.transform().rotation().z(), r1.transform().rotation().w()), 0.5, 1e-12);
  EXPECT_EQ(tf.transforms()[2].header().frame_id(), "robot1/odom");
  EXPECT_EQ(tf.transforms()[2].child_frame_id(), "robot1/base_link");
}

TEST(Ros2Output, EachObjectIsABoxALabelAndAnUncertaintyEllipsoid) {
  Fixture f;
  const auto m = to_markers(f.merged, 7);
  ASSERT_EQ(m.markers().size(), 4u);
  EXPECT_EQ(m.markers()[0].action(), 3);  // DELETEALL: merged-away objects vanish
  const auto& box = m.markers()[1];
  EXPECT_EQ(box.ns(), "objects");
  EXPECT_EQ(box.type(), 1);
  EXPECT_FLOAT_EQ(box.color().r(), 0.90f);  // victims are red
  EXPECT_DOUBLE_EQ(box.scale().x(), double(1.6f));
  EXPECT_EQ(m.markers()[2].text(), "victim 1-4 (0.93)");
  const auto& ellipse = m.markers()[3];
  EXPECT_EQ(ellipse.ns(), "uncertainty");
  // 2 sigma each way: diameters 4 * sqrt of the variances, largest along x.
  std::vector<double> d{ellipse.scale().x(), ellipse.scale().y(), ellipse.scale().z()};
  std::sort(d.begin(), d.end());
  EXPECT_NEAR(d[0], 0.2, 1e-9);
  EXPECT_NEAR(d[1], 0.4, 1e-9);
  EXPECT_NEAR(d[2], 0.8, 1e-9);
  EXPECT_EQ(box.id(), ellipse.id());
}

TEST(Ros2Output, ObjectCloudsArePackedXyzRgbPoints) {
  Fixture f;
  const auto c = to_object_cloud(f.merged, 7);
  EXPECT_EQ(c.width(), 2u);
  EXPECT_EQ(c.point_step(), 16u);
  ASSERT_EQ(c.data().size(), 32u);
  ASSERT_EQ(c.fields().size(), 4u);
  EXPECT_EQ(c.fields()[3].name(), "rgb");
  float z = 0;
  uint32_t rgb = 0;
  std::memcpy(&z, c.data().data() + 8, 4);
  std::memcpy(&rgb, c.data().data() + 12, 4);
  EXPECT_FLOAT_EQ(z, 3.f);
  EXPECT_EQ(rgb, 0xFF1001u);
}

TEST(Ros2Output, PathsCarryEveryMergedPoseAtItsMissionTime) {
  const Trajectory t{{1'000, SE2(0, 0, 0)}, {2'000, SE2(1, 2, 0.3)}};
  const auto p = to_path(t, 99);
  ASSERT_EQ(p.poses().size(), 2u);
  EXPECT_EQ(p.poses()[1].header().stamp().nanosec(), 2'000u);
  EXPECT_DOUBLE_EQ(p.poses()[1].pose().position().y(), 2.0);
}

}  // namespace
}  // namespace cairn::base

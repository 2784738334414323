// Duplicate merging at the base (global_object.h): one object seen by two robots becomes one
// object with an aligned cloud; two distinct nearby objects of the same class stay two; exports
// read back right after merging.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base_station/core/global_object.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"
#include "base_station/export/exporter.h"

namespace cairn::base {
namespace {

/// Visible half (facing `view_rad`; `arc_rad` of it) of an upright cylinder, in the object frame (centred).
ColoredCloud half_cylinder(double radius_m, double height_m, double view_rad, double arc_rad = M_PI) {
  ColoredCloud c;
  for (int k = 0; k < 40; ++k) {
    const double a = view_rad - arc_rad / 2 + arc_rad * k / 39.0;
    for (double z = -height_m / 2; z <= height_m / 2 + 1e-9; z += 0.02)
      c.push_back(ColoredPoint{float(radius_m * std::cos(a)), float(radius_m * std::sin(a)), float(z), 230,
                               uint8_t(120 + 100 * (k % 4 == 0)), 40});
  }
  return c;
}

ObjectReport report(ObjectId id, const ColoredCloud& cloud, int observations) {
  ObjectReport r;
  r.id = id;
  r.class_name = "victim";
  r.confidence = 0.7f + 0.1f * float(id.robot.value);
  r.observations = observations;
  r.size_m = Eigen::Vector3f(0.4f, 0.4f, 0.5f);
  r.cloud = cloud;
  return r;
}

Eigen::Isometry3d pose(double x, double y, double z, double yaw_rad = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() << x, y, z;
  return T;
}

TEST(ObjectMerge, OneObjectSeenByTwoRobotsBecomesOneAlignedObject) {
  // Robot 0 sees the west half, robot 1 the south half; robot 1's placement is off by 7 cm and 3 deg.
  const ObjectReport a = report({RobotId(0), 0}, half_cylinder(0.2, 0.5, M_PI), 12);
  const ObjectReport b = report({RobotId(1), 4}, half_cylinder(0.2, 0.5, -M_PI / 2), 4);
  const Eigen::Vector3d truth(4.0, 3.0, 0.25);
  const std::vector<PlacedObjectReport> placed{{&a, pose(truth.x(), truth.y(), truth.z())},
                                               {&b, pose(truth.x() + 0.06, truth.y() - 0.04, truth.z(), 0.05)}};
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(check.accepted) << check.reason;
  const std::vector<GlobalObject> objects = merge_object_reports(placed, {});
  ASSERT_EQ(objects.size(), 1u);
  const GlobalObject& o = objects[0];
  EXPECT_EQ(o.id, a.id);
  ASSERT_EQ(o.robots.size(), 2u);
  EXPECT_EQ(o.robots[1], RobotId(1));
  EXPECT_EQ(o.reports.size(), 2u);
  EXPECT_EQ(o.observations, 16);
  EXPECT_FLOAT_EQ(o.confidence, 0.8f);
  EXPECT_FALSE(o.merge_reason.empty());
  // Observation-weighted mean: (12 * truth + 4 * (truth + (0.06, -0.04))) / 16.
  EXPECT_NEAR(o.position_m.x(), truth.x() + 0.015, 1e-9);
  EXPECT_NEAR(o.position_m.y(), truth.y() - 0.01, 1e-9);
  // Aligned union: nearly every point within 2.5 cm of the cylinder around the merged position (an
  // unaligned union leaves robot 1's half up to 7 cm off).
  int off = 0;
  for (const ColoredPoint& p : o.cloud_global) {
    const double r = std::hypot(p.x - o.position_m.x(), p.y - o.position_m.y());
    off += std::abs(r - 0.2) > 0.025;
  }
  std::printf("merged cloud: %zu points, %d off the surface; %s\n", o.cloud_global.size(), off, o.merge_reason.c_str());
  EXPECT_LE(off, int(o.cloud_global.size() / 50));
}

TEST(ObjectMerge, TwoNearbyObjectsOfTheSameClassStayTwo) {
  // One robot's two victims 0.38 m apart (surfaces 0.08 m apart), both seen from the west: same
  // class, within the candidate gate, but ICP finds no overlap. (Two robots' reports this close are
  // within their relative placement error and cannot be told apart from one object.)
  const ObjectReport a = report({RobotId(0), 0}, half_cylinder(0.15, 0.5, M_PI), 8);
  const ObjectReport b = report({RobotId(0), 1}, half_cylinder(0.15, 0.5, M_PI), 8);
  const std::vector<PlacedObjectReport> placed{{&a, pose(4.0, 3.0, 0.25)}, {&b, pose(4.0, 3.38, 0.25)}};
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(check.candidate);
  EXPECT_FALSE(check.accepted) << check.reason;
  std::printf("distinct: %s\n", check.reason.c_str());
  EXPECT_EQ(merge_object_reports(placed, {}).size(), 2u);
}

TEST(ObjectMerge, OneObjectFromTwoRobotsPlacedThirtyCentimetresApartIsMerged) {
  // Robot 1's placement is off by 0.3 m (the robots' placement RMSE in the simulated missions):
  // beyond ICP's capture range from the placements, so the centres are made to coincide first.
  const ObjectReport a = report({RobotId(0), 0}, half_cylinder(0.25, 1.0, M_PI), 12);
  const ObjectReport b = report({RobotId(1), 2}, half_cylinder(0.25, 1.0, -M_PI / 2), 8);
  const Eigen::Vector3d truth(6.0, 2.0, 0.5);
  for (const double bearing : {0.0, 2.0, 4.0}) {
    const std::vector<PlacedObjectReport> placed{
        {&a, pose(truth.x(), truth.y(), truth.z())},
        {&b, pose(truth.x() + 0.3 * std::cos(bearing), truth.y() + 0.3 * std::sin(bearing), truth.z(), 0.04)}};
    const MergeCheck check = check_same_object(placed[0], placed[1], {});
    EXPECT_TRUE(check.accepted) << check.reason;
    std::printf("0.3 m apart, bearing %.0f rad: %s\n", bearing, check.reason.c_str());
    EXPECT_EQ(merge_object_reports(placed, {}).size(), 1u);
  }
}

TEST(ObjectMerge, OneObjectSeenFromOppositeSidesIsMergedByItsCentre) {
  // Robot 0 sees the west side, robot 1 the east side (140 deg each): no shared surface, ICP cannot
  // verify. Their reported centres (primitive fits) coincide within 4 cm: one victim, not two.
  const ObjectReport a = report({RobotId(0), 0}, half_cylinder(0.2, 0.5, M_PI, 2.4), 10);
  const ObjectReport b = report({RobotId(1), 0}, half_cylinder(0.2, 0.5, 0.0, 2.4), 10);
  const std::vector<PlacedObjectReport> placed{{&a, pose(5.0, 2.0, 0.25)}, {&b, pose(5.03, 2.02, 0.25)}};
  ObjectMergeOptions icp_only;
  icp_only.max_coincident_centre_m = 0.0;
  const MergeCheck by_icp = check_same_object(placed[0], placed[1], icp_only);
  ASSERT_FALSE(by_icp.accepted) << "the sides overlap: the test lost its point; " << by_icp.reason;
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(check.accepted) << check.reason;
  std::printf("opposite sides: %s\n", check.reason.c_str());
  ASSERT_EQ(merge_object_reports(placed, {}).size(), 1u);
  // The same two views 0.2 m apart are two objects: the centres no longer coincide.
  const std::vector<PlacedObjectReport> apart{{&a, pose(5.0, 2.0, 0.25)}, {&b, pose(5.2, 2.0, 0.25)}};
  EXPECT_FALSE(check_same_object(apart[0], apart[1], {}).accepted);
  // Two different victims whose fitted centres coincide cannot both be whole: a cloud twice an
  // object's size is not one object.
  ColoredCloud wide = half_cylinder(0.2, 0.5, 0.0, 2.4);
  for (ColoredPoint& p : wide) p.x += 0.6f;
  const ObjectReport c = report({RobotId(1), 1}, wide, 10);
  const std::vector<PlacedObjectReport> odd{{&a, pose(5.0, 2.0, 0.25)}, {&c, pose(5.03, 2.0, 0.25)}};
  EXPECT_FALSE(check_same_object(odd[0], odd[1], {}).accepted);
}

TEST(ObjectMerge, TwoRobotsVictimsOneMetreApartStayTwo) {
  // Two distinct victims 1 m apart, each seen by another robot, one placement 0.15 m off toward
  // the other: a wrong merge would lose a victim.
  const ObjectReport a = report({RobotId(0), 0}, half_cylinder(0.25, 1.0, M_PI), 12);
  const ObjectReport b = report({RobotId(1), 0}, half_cylinder(0.25, 1.0, M_PI), 12);
  const std::vector<PlacedObjectReport> placed{{&a, pose(6.0, 2.0, 0.5)}, {&b, pose(6.0, 2.85, 0.5)}};
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_FALSE(check.accepted) << check.reason;
  std::printf("1 m apart: %s\n", check.reason.c_str());
  EXPECT_EQ(merge_object_reports(placed, {}).size(), 2u);
}

/// The visible surface of a box lying on the floor (top and the four sides), centred, in its own frame.
ColoredCloud lying_box(double length_m, double width_m, double height_m) {
  ColoredCloud c;
  const auto add = [&](double x, double y, double z) {
    c.push_back(ColoredPoint{float(x), float(y), float(z), 220, uint8_t(30 + 60 * (int(x * 10) % 2)), 30});
  };
  for (double x = -length_m / 2; x <= length_m / 2 + 1e-9; x += 0.02) {
    for (double y = -width_m / 2; y <= width_m / 2 + 1e-9; y += 0.02) add(x, y, height_m / 2);
    for (double z = -height_m / 2; z <= height_m / 2 + 1e-9; z += 0.02) add(x, -width_m / 2, z), add(x, width_m / 2, z);
  }
  for (double y = -width_m / 2; y <= width_m / 2 + 1e-9; y += 0.02)
    for (double z = -height_m / 2; z <= height_m / 2 + 1e-9; z += 0.02)
      add(-length_m / 2, y, z), add(length_m / 2, y, z);
  return c;
}

TEST(ObjectMerge, AnEndOfALyingVictimSeenAloneJoinsTheWholeVictim) {
  // A victim lying diagonally (1.6 x 0.5 m, the collapsed floor's); early, from far, the robot saw
  // only its north-east end and reported it as an object of its own, the fitted centre 0.85 m from
  // the whole victim's (the demo left such ends as second victims).
  ObjectReport whole = report({RobotId(0), 0}, lying_box(1.6, 0.5, 0.3), 60);
  whole.size_m = Eigen::Vector3f(1.35f, 1.6f, 0.3f);
  ColoredCloud end_cloud;
  for (ColoredPoint p : whole.cloud)
    if (p.x > 0.6f) p.x -= 0.85f, end_cloud.push_back(p);  // in the end report's frame
  ObjectReport end = report({RobotId(0), 1}, end_cloud, 4);
  end.size_m = Eigen::Vector3f(0.3f, 0.4f, 0.3f);
  const Eigen::Isometry3d T_whole = pose(6.6, 1.8, 0.15, -0.9);
  Eigen::Isometry3d T_end = T_whole;
  T_end.translation() += T_whole.linear() * Eigen::Vector3d(0.85, 0.0, 0.0);
  const std::vector<PlacedObjectReport> placed{{&whole, T_whole}, {&end, T_end}};
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(check.accepted) << check.reason;
  std::printf("end of a lying victim: %s\n", check.reason.c_str());
  EXPECT_EQ(merge_object_reports(placed, {}).size(), 1u);

  // A second victim (a 0.5 m cylinder) lying against the same end, its box touching the first's,
  // is a candidate now but stays its own: no surface of the first victim matches it.
  const ObjectReport other = report({RobotId(0), 2}, half_cylinder(0.25, 0.5, -0.9 + M_PI), 20);
  Eigen::Isometry3d T_other = T_whole;
  T_other.translation() += T_whole.linear() * Eigen::Vector3d(1.07, 0.0, 0.1);
  const MergeCheck against = check_same_object(placed[0], {&other, T_other}, {});
  EXPECT_TRUE(against.candidate) << against.reason;
  EXPECT_FALSE(against.accepted) << against.reason;
}

TEST(ObjectMerge, AReportPlacedByTheFloorAloneIsComparedAcrossTheFloor) {
  // From 8.5 m, beyond the depth camera, robot 3 placed an exit by the ground homography: no cloud,
  // its centre on the floor. Robot 0 saw the door's cloud, centred 1 m up, 0.3 m across from it.
  ObjectReport door = report({RobotId(0), 4}, half_cylinder(0.4, 2.0, M_PI), 90);
  door.class_name = "exit";
  ObjectReport far = report({RobotId(3), 0}, {}, 3);
  far.class_name = "exit";
  const std::vector<PlacedObjectReport> placed{{&door, pose(10.7, 9.95, 1.0)}, {&far, pose(10.7, 9.65, 0.0)}};
  const MergeCheck check = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(check.accepted) << check.reason;
  EXPECT_EQ(merge_object_reports(placed, {}).size(), 1u);
  // 1.2 m across the floor is another door.
  const std::vector<PlacedObjectReport> apart{{&door, pose(10.7, 9.95, 1.0)}, {&far, pose(10.7, 8.75, 0.0)}};
  EXPECT_FALSE(check_same_object(apart[0], apart[1], {}).accepted);
}

TEST(ObjectMerge, EmptyAndDegenerateCloudsDoNotCrash) {
  ObjectReport a = report({RobotId(0), 0}, {}, 3);
  ObjectReport b = report({RobotId(1), 0}, {}, 3);
  std::vector<PlacedObjectReport> placed{{&a, pose(1, 1, 0)}, {&b, pose(1.1, 1, 0)}};
  MergeCheck c = check_same_object(placed[0], placed[1], {});
  EXPECT_TRUE(c.accepted) << c.reason;  // no clouds: the centroid gate decides
  EXPECT_NE(c.reason.find("too few points"), std::string::npos);
  ColoredCloud plane;  // a flat patch: ICP is degenerate, overlap still decides
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) plane.push_back(ColoredPoint{0.03f * i, 0.03f * j, 0.f, 200, 50, 50});
  a.cloud = plane, b.cloud = plane;
  c = check_same_object(placed[0], placed[1], {});
  EXPECT_FALSE(c.reason.empty());
  EXPECT_EQ(merge_object_reports({}, {}).size(), 0u);
}

TEST(ObjectMerge, ExportsReadBackAfterMerging) {
  MapperOptions options;
  options.detect_loops = false;
  MultiRobotMapper mapper(options);
  mapper.set_robot_start(RobotId(0), testing::left_path()[0]);
  mapper.set_robot_start(RobotId(1), testing::right_path()[0]);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(0), testing::left_path(), testing::room_walls()))
    mapper.add_keyframe(kf);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(1), testing::right_path(), testing::room_walls()))
    mapper.add_keyframe(kf);
  const Eigen::Vector3d victim(4.2, 3.4, 0.25);
  auto place = [&](ObjectReport r, int anchor, const SE2& anchor_world, double dx, double dy = 0.0) {
    r.anchor_seq = anchor;
    r.stamp_ns = kNsPerSec * (anchor + 1);
    r.T_anchor_object = anchor_world.to_isometry3().inverse() * pose(victim.x() + dx, victim.y() + dy, victim.z());
    EXPECT_NE(mapper.add_object(r).status, AddStatus::kRejected);
  };
  place(report({RobotId(0), 0}, half_cylinder(0.2, 0.5, M_PI), 6), 3, testing::left_path()[3], 0.0);
  place(report({RobotId(1), 0}, half_cylinder(0.2, 0.5, -M_PI / 2), 6), 4, testing::right_path()[4], 0.05);
  place(report({RobotId(1), 1}, half_cylinder(0.2, 0.5, 0.0), 6), 1, testing::right_path()[1], 3.5, -1.0);  // far away
  mapper.optimize();
  const std::vector<GlobalObject> objects = mapper.objects();
  ASSERT_EQ(objects.size(), 2u);
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("cairn_merge_" + std::to_string(::getpid()))).string();
  ASSERT_TRUE(export_all(mapper.merged(), dir).ok());
  std::ifstream in(dir + "/objects.geojson");
  const nlohmann::json geo = nlohmann::json::parse(in);
  ASSERT_EQ(geo["features"].size(), 2u);
  const auto& f = geo["features"][0];
  EXPECT_EQ(f["properties"]["class"], "victim");
  EXPECT_NEAR(f["properties"]["confidence"].get<double>(), 0.8, 1e-6);
  EXPECT_EQ(f["properties"]["robots"], nlohmann::json({0, 1}));
  EXPECT_NEAR(f["geometry"]["coordinates"][0].get<double>(), objects[0].position_m.x(), 1e-6);
  EXPECT_NEAR(f["geometry"]["coordinates"][0].get<double>(), victim.x() + 0.025, 0.03);
  EXPECT_NEAR(f["geometry"]["coordinates"][1].get<double>(), victim.y(), 0.03);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/objects.bt"));
  for (const GlobalObject& o : objects) {
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
    ASSERT_EQ(pcl::io::loadPLYFile(dir + "/object_" + object_key(o.id) + ".ply", cloud), 0);
    EXPECT_EQ(cloud.size(), o.cloud_global.size());
    for (size_t i = 0; i < cloud.size(); i += 17) {
      octomap::OcTreeNode* node = tree.search(cloud[i].x, cloud[i].y, cloud[i].z);
      ASSERT_NE(node, nullptr);
      EXPECT_TRUE(tree.isNodeOccupied(node));
    }
  }
  int ply_files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) ply_files += e.path().extension() == ".ply";
  EXPECT_EQ(ply_files, 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cairn::base

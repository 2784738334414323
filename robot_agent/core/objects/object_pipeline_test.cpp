#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "robot_agent/core/objects/object_detector.h"
#include "robot_agent/core/objects/object_tracker.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

// 320x240 grey frame at 4 m with a red 40x40 px box at 2 m centred on the principal point, a
// yellow 30x30 box at 3 m, and a red 4x4 speck (below min area).
RgbdFrame synthetic_frame() {
  RgbdFrame f = testing::grey_wall_frame();
  testing::paint_square(&f, 140, 100, 40, 220, 20, 20, 2000);
  testing::paint_square(&f, 20, 20, 30, 230, 200, 20, 3000);
  testing::paint_square(&f, 280, 200, 4, 220, 20, 20, 1000);
  return f;
}

TEST(ObjectDetector, FindsRedBoxWithCorrectCentroid) {
  ObjectDetector detector;
  const std::vector<Detection> dets = detector.detect(synthetic_frame());
  ASSERT_EQ(dets.size(), 2u);
  const Detection& victim = dets[0];
  EXPECT_EQ(victim.class_name, "victim");
  EXPECT_EQ(victim.area_px, 1600);
  // Camera at (0.1, 0, 0.4) looking along base x: the box centre is 2 m ahead of it.
  EXPECT_LT((victim.centroid_base - Eigen::Vector3d(2.1, 0.0, 0.4)).norm(), 0.02);
  EXPECT_NEAR(victim.median_depth_m, 2.0, 1e-9);
  EXPECT_FALSE(victim.cloud_base.empty());
  EXPECT_LT(victim.cloud_base.size(), 1600u);  // voxel-filtered
  EXPECT_GT(victim.cloud_base.front().r, 200);
  const cv::Mat thumb = cv::imdecode(victim.thumbnail_jpeg, cv::IMREAD_COLOR);
  ASSERT_FALSE(thumb.empty());
  EXPECT_LE(std::max(thumb.cols, thumb.rows), 96);
  EXPECT_EQ(dets[1].class_name, "hazard");
}

TEST(ObjectDetector, InvalidFrameGivesNothing) {
  RgbdFrame f = synthetic_frame();
  f.depth.pop_back();
  EXPECT_FALSE(f.valid());
  EXPECT_TRUE(ObjectDetector().detect(f).empty());
}

TEST(ObjectTracker, KeepsOneIdAndPublishesAfterThreeFrames) {
  ObjectDetector detector;
  ObjectTracker tracker(RobotId(2));
  const Anchor anchor{4, SE2(1.0, 0.0, M_PI / 2)};
  std::vector<ObjectReport> all;
  for (int i = 0; i < 12; ++i) {
    RgbdFrame f = synthetic_frame();
    f.stamp_ns = 1000 + i;
    // The robot moves 1 cm per frame; the object stays put in the local frame.
    const SE2 T_local_base(0.01 * i, 0.0, 0.0);
    std::vector<Detection> dets = detector.detect(f);
    for (Detection& d : dets) d.centroid_base.x() -= 0.01 * i;
    const auto reports = tracker.update(f.stamp_ns, dets, T_local_base, anchor);
    if (i < 2) EXPECT_TRUE(reports.empty());
    if (i == 2) EXPECT_EQ(reports.size(), 2u);  // victim and hazard confirmed
    all.insert(all.end(), reports.begin(), reports.end());
  }
  EXPECT_EQ(tracker.num_tracks(), 2u);
  ASSERT_FALSE(all.empty());
  const ObjectReport& r = all.front();
  EXPECT_EQ(r.id, (ObjectId{RobotId(2), 0}));
  EXPECT_EQ(r.class_name, "victim");
  EXPECT_EQ(r.anchor_seq, 4);
  EXPECT_EQ(r.observations, 3);
  EXPECT_NEAR(r.confidence, 1.0 - std::exp(-1.0), 1e-6);
  // Object at local (2.1, 0, 0.4); anchor at (1, 0) facing +y: object is 1.1 m to its right.
  const Eigen::Vector3d t = r.T_anchor_object.translation();
  EXPECT_LT((t - Eigen::Vector3d(0.0, -1.1, 0.4)).norm(), 0.02);
  EXPECT_GT(r.size_m.y(), 0.25);  // 40 px at 2 m ~ 0.31 m
  EXPECT_LE(r.cloud.size(), 3000u);
  EXPECT_FALSE(r.thumbnail_jpeg.empty());
  for (const ObjectReport& rep : all) EXPECT_TRUE(rep.id.seq == 0 || rep.id.seq == 1);
}

}  // namespace
}  // namespace cairn::agent

namespace cairn::agent {
namespace {

TEST(ObjectDetector, MissingDepthFallsBackToGroundHomography) {
  RgbdFrame f = synthetic_frame();
  std::fill(f.depth.begin(), f.depth.end(), 0);
  const DetectionFrame r = ObjectDetector().analyse(f);
  EXPECT_TRUE(r.converged);
  EXPECT_NE(r.reason.find("homography"), std::string::npos);
  for (const Detection& d : r.detections) {
    EXPECT_FALSE(d.has_depth);
    EXPECT_TRUE(d.cloud_base.empty());
    EXPECT_TRUE(d.centroid_base.allFinite());
  }
}

TEST(ObjectDetector, EmptyFrameGivesAReason) {
  const DetectionFrame r = ObjectDetector().analyse(RgbdFrame{});
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.reason.empty());
}

TEST(ObjectTracker, SurvivesEmptyCloudsAndNonFiniteDetections) {
  ObjectTracker tracker(RobotId(1));
  Detection d;
  d.class_name = "victim";
  d.centroid_base = Eigen::Vector3d(2, 0, 0.3);
  d.camera_base = Eigen::Vector3d(0.1, 0, 0.5);
  Detection bad = d;
  bad.centroid_base.x() = std::numeric_limits<double>::quiet_NaN();
  std::vector<ObjectReport> all;
  for (int i = 0; i < 5; ++i) {
    const auto r = tracker.update(1000 + i, {d, bad}, SE2(), Anchor{0, SE2()});
    all.insert(all.end(), r.begin(), r.end());
  }
  EXPECT_EQ(tracker.num_tracks(), 1u);
  ASSERT_FALSE(all.empty());
  EXPECT_TRUE(all.front().cloud.empty());
  EXPECT_LT((all.front().T_anchor_object.translation() - d.centroid_base).norm(), 1e-6);
}

}  // namespace
}  // namespace cairn::agent
